// pipeline/cpu/cpu_integrate.h against kernels/volume.h's integrateVoxel(): every row of voxels must end
// bit-identical, over rows that cross free space, the truncation band, the space behind the surface and the
// outside of the view, from voxels in every state (unobserved, partly and fully weighted, negative tsdf).
// And the CPU backend's whole integrate (rows, block culling of pipeline/integrate_cull.h) against
// integrateVoxel() on every voxel, and the empty-space skipping masks it or-s in row by row against
// kernels/raycast.h's sbBlockSurfaceMask.

#include <catch2/catch.hpp>
#include <cstring>
#include <random>
#include <vector>

#include "kernels/raycast.h"
#include "kernels/volume.h"
#include "pipeline/block_distance.h"
#include "pipeline/cpu/cpu_backend.h"
#include "pipeline/cpu/cpu_integrate.h"
#include "pipeline/kernel_args.h"
#include "tests/pipeline/synthetic_room.h"

namespace {

constexpr int kResolution = 128;
constexpr float kVolumeSize = 3.2f;  // metres: the room (x 0.9-2.2, y 1.0-2.0, z up to 2.7) fits
constexpr float kMu = 0.1f;
constexpr int kMaxWeight = 100;

// Voxels in every state: unobserved (+1, 0), random tsdf with weights 1..max, and some at the maximum weight.
std::vector<int16_t> randomRow(std::mt19937& rng) {
  std::uniform_int_distribution<int> tsdf(-32767, 32767), weight(0, kMaxWeight), kind(0, 3);
  std::vector<int16_t> row(2 * kResolution);
  for (int x = 0; x < kResolution; ++x) {
    const int k = kind(rng);
    row[2 * x] = static_cast<int16_t>(k == 0 ? 32767 : tsdf(rng));
    row[2 * x + 1] = static_cast<int16_t>(k == 0 ? 0 : (k == 1 ? kMaxWeight : weight(rng)));
  }
  return row;
}

}  // namespace

TEST_CASE("integrateRow leaves every voxel bit-identical to integrateVoxel", "[pipeline][integrate]") {
  const sb::test::Room room;
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(1.5, 1.5, 0.9);
  pose = pose * sb::test::motion({0.02, -0.03, 0.05}, 7.0, {0.2, 1.0, 0.1});
  const sb::DepthFrame frame = sb::test::renderRoom(room, pose, k);
  std::vector<float> depth(static_cast<size_t>(k.width) * k.height);
  for (int y = 0; y < k.height; ++y)
    for (int x = 0; x < k.width; ++x)
      depth[static_cast<size_t>(y) * k.width + x] = static_cast<float>(frame.depth(x, y) / sb::test::kRoomDepthScale);
  for (int x = 20; x < 40; ++x) depth[60 * k.width + x] = 0.0f;  // a hole: no reading
  const SbMat34 w2c = sb::toMat34(pose.inverse().cast<float>().matrix());
  const SbCamera camera = sb::toCamera(k);
  const float voxel = kVolumeSize / kResolution;
  const float3 step = sbRotate(w2c, sbMakeFloat3(voxel, 0.0f, 0.0f));
  std::mt19937 rng(7);
  // What the rows exercised: surface band (tsdf < 1), free space (+1), behind the surface, outside the view.
  int band = 0, free = 0, untouched = 0, rows = 0;
  for (int z = 0; z < kResolution; z += 3) {
    for (int y = 0; y < kResolution; y += 5) {
      const float3 base = sbTransform(w2c, sbMakeFloat3(0.5f * voxel, (y + 0.5f) * voxel, (z + 0.5f) * voxel));
      // Rows from random voxels and from unobserved ones (+1, 0): on the latter, what a voxel became tells
      // which case it took.
      for (const bool unobserved : {false, true}) {
        std::vector<int16_t> start = randomRow(rng);
        if (unobserved)
          for (int x = 0; x < kResolution; ++x) start[2 * x] = 32767, start[2 * x + 1] = 0;
        // Whole rows and ranges of every length modulo 4 at every alignment.
        const int x0 = (y + z) % 7, x1 = kResolution - (y * 3 + z) % 5;
        std::vector<int16_t> expected = start, actual = start;
        for (int x = x0; x < x1; ++x)
          integrateVoxel(expected.data(), x, base + step * static_cast<float>(x), depth.data(), k.width, k.height,
                         camera, kMu, kMaxWeight);
        sb::integrateRow(actual.data(), 0, x0, x1, base, step, depth.data(), k.width, k.height, camera, kMu, kMaxWeight);
        INFO("row y " << y << " z " << z << " x " << x0 << ".." << x1 << (unobserved ? " unobserved" : " random"));
        REQUIRE(std::memcmp(expected.data(), actual.data(), expected.size() * sizeof(int16_t)) == 0);
        ++rows;
        if (unobserved)
          for (int x = 0; x < kResolution; ++x) {
            if (expected[2 * x + 1] == 0)
              ++untouched;
            else if (expected[2 * x] == 32767)
              ++free;
            else
              ++band;
          }
      }
    }
  }
  INFO("band " << band << " free " << free << " untouched " << untouched);
  CHECK(rows > 1000);
  CHECK(band > 1000);
  CHECK(free > 2000);
  CHECK(untouched > 10000);
}

TEST_CASE("CpuBackend::integrate with block culling leaves the volume bit-identical to integrateVoxel() on every voxel",
          "[pipeline][integrate]") {
  sb::PipelineConfig config;
  config.volumeSize = kVolumeSize;
  config.volumeResolution = kResolution;
  config.mu = kMu;
  config.maxWeight = kMaxWeight;
  const sb::Intrinsics full = sb::test::roomIntrinsics(160, 120);
  sb::ThreadPool pool(2);
  sb::CpuBackend cpu(config, full, pool);
  std::vector<int16_t> expected(2 * static_cast<size_t>(kResolution) * kResolution * kResolution);
  for (size_t i = 0; i < expected.size(); i += 2) expected[i] = 32767, expected[i + 1] = 0;
  const sb::test::Room room;
  // Poses across the room, one of them 0.25 m from the back wall (blocks closer than the culling's near guard),
  // at csr 1 and 2, with holes (every 29th pixel and a whole band of rows without readings) and spikes.
  struct View {
    Eigen::Vector3d position;
    double degrees;
    Eigen::Vector3d axis;
    int csr;
  };
  const std::vector<View> views = {{{1.5, 1.5, 0.9}, 0.0, {0, 1, 0}, 1},    {{1.5, 1.5, 0.9}, 0.0, {0, 1, 0}, 1},
                                   {{1.4, 1.45, 1.0}, 20.0, {0.2, 1, 0}, 2}, {{1.6, 1.55, 0.8}, -25.0, {0, 1, 0.3}, 1},
                                   {{1.5, 1.5, 2.45}, 10.0, {1, 0, 0}, 1},   {{1.2, 1.3, 0.5}, 35.0, {0, 1, 0}, 2}};
  size_t culled = 0, blocks = 0;
  for (size_t i = 0; i < views.size(); ++i) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = views[i].position;
    pose = pose * sb::test::motion({0, 0, 0}, views[i].degrees, views[i].axis);
    sb::DepthRaw raw = sb::test::renderRoom(room, pose, full).depth;
    for (size_t p = 0; p < raw.size(); p += 29) raw.pixels()[p] = 0;
    // Single far pixels (30% deeper): a footprint that missed one would cull voxels that it updates.
    for (size_t p = 0; p < raw.size(); p += 41) raw.pixels()[p] = static_cast<uint16_t>(raw.pixels()[p] * 1.3);
    for (int y = 70; y < 80; ++y)
      for (int x = 0; x < full.width; ++x) raw.pixels()[static_cast<size_t>(y) * full.width + x] = 0;
    sb::StageTimes times;
    cpu.preprocess(raw, static_cast<float>(1.0 / sb::test::kRoomDepthScale), views[i].csr, times);
    const Eigen::Isometry3f posef = pose.cast<float>();
    cpu.integrate(posef, times);
    culled += cpu.integrateCull().culledCount();
    blocks += static_cast<size_t>(cpu.integrateCull().blocks()) * cpu.integrateCull().blocks() * cpu.integrateCull().blocks();
    const sb::Intrinsics k = full.scaled(views[i].csr);
    const SbMat34 w2c = sb::toMat34(posef.inverse().matrix());
    // Voxel positions as the backend computes them (row start + step * x: rounding differs from integrate()'s
    // per-voxel transform), every voxel through integrateVoxel.
    const float voxel = kVolumeSize / kResolution;
    const float3 step = sbRotate(w2c, sbMakeFloat3(voxel, 0.0f, 0.0f));
    for (int z = 0; z < kResolution; ++z)
      for (int y = 0; y < kResolution; ++y) {
        const float3 base = sbTransform(w2c, sbMakeFloat3(0.5f * voxel, (y + 0.5f) * voxel, (z + 0.5f) * voxel));
        int16_t* row = expected.data() + 2 * (static_cast<size_t>(z) * kResolution + y) * kResolution;
        for (int x = 0; x < kResolution; ++x)
          integrateVoxel(row, x, base + step * static_cast<float>(x), cpu.rawMetres().data(), k.width, k.height,
                         sb::toCamera(k), kMu, kMaxWeight);
      }
    INFO("view " << i);
    REQUIRE(std::memcmp(expected.data(), cpu.volumeData(), expected.size() * sizeof(int16_t)) == 0);
    // The masks: those of sbBlockSurfaceMask on the volume, plus stale bits only in blocks that the integration
    // did not visit whole (or-ed into the old mask); from the empty volume (first view) exactly those.
    const int n = kResolution >> sb::CpuBackend::kSkipShift;
    const int below = sb::surfaceTsdfBelow(config.raycastSmallStepBelow);
    size_t stale = 0, withSurface = 0;
    for (int bz = 0; bz < n; ++bz)
      for (int by = 0; by < n; ++by)
        for (int bx = 0; bx < n; ++bx) {
          const uint8_t mask = sbBlockSurfaceMask(cpu.volumeData(), kResolution, SbVoxelOffset{}, sb::CpuBackend::kSkipShift, below,
                                                  bx, by, bz);
          const uint8_t got = cpu.blockSurfaceMasks()[bx + (by + static_cast<size_t>(bz) * n) * n];
          REQUIRE((got & mask) == mask);
          if (got != mask) ++stale;
          if (mask != 0) ++withSurface;
        }
    INFO(stale << " stale masks, " << withSurface << " blocks with surface");
    CHECK(withSurface > 0);
    if (i == 0) CHECK(stale == 0);
  }
  // The culling must have had work to skip, or this test proves nothing about it.
  INFO(culled << " of " << blocks << " blocks culled");
  CHECK(culled > blocks / 4);
}
