// Issue 43: per-block carving (pipeline/carve_schedule.h, config integrate_carve_blocks). A block in view is
// carved when it first comes into the volume's view, then once every integrate_carve_every integrations; the
// surface blocks every integration; the record follows the moving volume.

#include <catch2/catch.hpp>
#include <vector>

#include "pipeline/carve_schedule.h"
#include "pipeline/cpu/cpu_backend.h"
#include "tests/pipeline/logical_volume.h"
#include "tests/pipeline/synthetic_room.h"

namespace {

using sb::test::kRoomDepthScale;

constexpr int kRes = 128;  // blocks of 0.2 m: most of a view's blocks are seen whole
constexpr int kBlocks = kRes / 8;

sb::PipelineConfig config(int carveEvery, bool perBlock) {
  sb::PipelineConfig c;
  c.volumeResolution = kRes;
  c.volumeSize = 3.2f;
  c.integrateCarveEvery = carveEvery;
  c.integrateCarveBlocks = perBlock;
  return c;
}

std::vector<int16_t> logical(sb::CpuBackend& b) { return sb::test::logicalVolume(b, kRes); }

sb::DepthRaw constantDepth(const sb::Intrinsics& k, double metres) {
  sb::DepthRaw raw(k.width, k.height);
  for (size_t p = 0; p < raw.size(); ++p) raw.pixels()[p] = static_cast<uint16_t>(metres * kRoomDepthScale);
  return raw;
}

Eigen::Isometry3f at(float x, float y, float z, float yawDeg = 0.0f) {
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.translation() = Eigen::Vector3f(x, y, z);
  pose.linear() =
      Eigen::AngleAxisf(yawDeg * float(M_PI / 180.0), Eigen::Vector3f::UnitY()).toRotationMatrix();
  return pose;
}

void integrate(sb::CpuBackend& b, const sb::DepthRaw& raw, const Eigen::Isometry3f& pose,
               sb::StageTimes& times) {
  b.preprocess(raw, float(1.0 / kRoomDepthScale), 1, times);
  b.integrate(pose, times);
}

// Voxels that `reference` has fused or carved (weight > 0) and `b` has not.
size_t missed(sb::CpuBackend& b, sb::CpuBackend& reference) {
  const std::vector<int16_t> v = logical(b), r = logical(reference);
  size_t n = 0;
  for (size_t i = 0; i < v.size(); i += 2) n += r[i + 1] > 0 && v[i + 1] == 0;
  return n;
}

}  // namespace

TEST_CASE("carve schedule: the first view is carved as KinectFusion carves it, then every Nth integration",
          "[pipeline][integrate]") {
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  sb::ThreadPool pool(2);
  sb::CpuBackend blocks(config(4, true), k, pool), carving(config(1, false), k, pool);
  const sb::DepthRaw raw = constantDepth(k, 1.5);
  sb::StageTimes first, carvingTimes;
  integrate(blocks, raw, at(1.6f, 1.6f, 0.2f), first);
  integrate(carving, raw, at(1.6f, 1.6f, 0.2f), carvingTimes);
  // Every block in view visited whole: the same voxels, bit for bit, as the carving integration.
  CHECK(logical(blocks) == logical(carving));
  CHECK(blocks.carveSchedule().carvedOnly() > 0);
  // ... from fewer blocks: the cull keeps the blocks behind the camera (its near guard), the schedule does
  // not.
  CHECK(first.work.integrateBlocks < carvingTimes.work.integrateBlocks);
  // Then only the band and the blocks never seen whole (at the image's edges: carved every integration until
  // seen whole), except at the 5th and 9th (4 integrations after the last carving), which visit the whole
  // view.
  const size_t whole = blocks.carveSchedule().carvedOnly();
  size_t edges = 0;
  for (int i = 2; i <= 9; ++i) {
    sb::StageTimes times;
    integrate(blocks, raw, at(1.6f, 1.6f, 0.2f), times);
    INFO("integration " << i << ": " << blocks.carveSchedule().carvedOnly() << " blocks carved, " << whole
                        << " at the first");
    if (i == 2) edges = blocks.carveSchedule().carvedOnly();
    const bool due = i == 5 || i == 9;
    CHECK(blocks.carveSchedule().carvedOnly() == (due ? whole : edges));
    if (due) CHECK(times.work.integrateBlocks == first.work.integrateBlocks);
  }
  CHECK(edges < whole);  // the share of edge blocks shrinks as blocks get small against the view
}

TEST_CASE("carve schedule: blocks that come into view are carved at once, the rest not again",
          "[pipeline][integrate]") {
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  sb::ThreadPool pool(2);
  sb::CpuBackend blocks(config(100, true), k, pool), carving(config(1, false), k, pool);
  const sb::DepthRaw raw = constantDepth(k, 1.2);
  sb::StageTimes times;
  for (sb::CpuBackend* b : {&blocks, &carving}) integrate(*b, raw, at(1.6f, 1.6f, 0.4f), times);
  // Turned by 30 degrees: part of the view is new.
  sb::StageTimes turned, reference;
  integrate(blocks, raw, at(1.6f, 1.6f, 0.4f, 30.0f), turned);
  integrate(carving, raw, at(1.6f, 1.6f, 0.4f, 30.0f), reference);
  CHECK(blocks.carveSchedule().carvedOnly() > 0);
  CHECK(missed(blocks, carving) == 0);  // nothing the full carving reached is left unvisited
  CHECK(turned.work.integrateBlocks < reference.work.integrateBlocks);
}

TEST_CASE("carve schedule: the record moves with the volume, the blocks that come in were never carved",
          "[pipeline][integrate][volume_window]") {
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  sb::ThreadPool pool(2);
  sb::CpuBackend blocks(config(100, true), k, pool);
  const sb::DepthRaw raw = constantDepth(k, 1.5);
  sb::StageTimes times;
  integrate(blocks, raw, at(1.6f, 1.6f, 0.8f), times);
  integrate(blocks, raw, at(1.6f, 1.6f, 0.8f),
            times);  // ages 0 (seen whole), 1 (out of view), kNever (never)
  const size_t edges = blocks.carveSchedule().carvedOnly();  // the blocks never seen whole, carved again
  std::vector<uint8_t> before;
  const sb::CarveSchedule& record = blocks.carveSchedule();
  for (int bz = 0; bz < kBlocks; ++bz)
    for (int by = 0; by < kBlocks; ++by)
      for (int bx = 0; bx < kBlocks; ++bx) before.push_back(record.age(bx, by, bz));
  // One block along z: logical block z now holds what block z + 1 held; the last plane of blocks is new.
  blocks.moveVolume(Eigen::Vector3i(0, 0, 8));
  size_t kept = 0;
  for (int bz = 0; bz < kBlocks; ++bz)
    for (int by = 0; by < kBlocks; ++by)
      for (int bx = 0; bx < kBlocks; ++bx) {
        const uint8_t expected = bz + 1 < kBlocks ? before[size_t(bx + kBlocks * (by + kBlocks * (bz + 1)))]
                                                  : sb::CarveSchedule::kNever;
        kept += record.age(bx, by, bz) == expected;
      }
  CHECK(kept == size_t(kBlocks) * kBlocks * kBlocks);
  // The same view after the move: the same blocks (one block further in the volume's frame) are due, the
  // ones seen whole are not carved again.
  integrate(blocks, raw, at(1.6f, 1.6f, 0.8f), times);
  CHECK(blocks.carveSchedule().carvedOnly() == edges);
}
