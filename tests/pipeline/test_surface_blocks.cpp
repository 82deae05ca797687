// Issue 43: the surface block list (pipeline/surface_blocks.h) and the raycast's ray bounds
// (pipeline/ray_bounds.h). An integration over the list must leave every voxel of the truncation band exactly
// as the carving integration (every block in view) does, and differ from it only where that one carved free
// space (+1); the ray bounds must leave the raycast's maps bit-identical to the march without them.

#include <catch2/catch.hpp>
#include <cstring>
#include <vector>

#include "kernels/raycast.h"
#include "pipeline/block_distance.h"
#include "pipeline/cpu/cpu_backend.h"
#include "pipeline/kernel_args.h"
#include "pipeline/ray_bounds.h"
#include "pipeline/surface_blocks.h"
#include "tests/pipeline/logical_volume.h"
#include "tests/pipeline/synthetic_room.h"

namespace {

using sb::test::kRoomDepthScale;

constexpr int kRes = 64;
constexpr float kSize = 3.2f;

sb::PipelineConfig config(int carveEvery) {
  sb::PipelineConfig c;
  c.volumeResolution = kRes;
  c.volumeSize = kSize;
  c.integrateCarveEvery = carveEvery;
  return c;
}

std::vector<int16_t> logical(sb::CpuBackend& b) { return sb::test::logicalVolume(b, kRes); }

struct Outcome {
  size_t band = 0;       // voxels below +1 after the integration
  size_t carvedOnly = 0;  // voxels only the carving integration updated (to +1)
};

// Integrates `raw` at `pose` into a surface-only and a carving backend (both moved to `corner` first) and
// checks every voxel: the same in both, or carved (+1, weight 1) by the carving one and untouched (+1, 0) in
// the other.
Outcome compare(const sb::DepthRaw& raw, const Eigen::Isometry3d& pose, const sb::Intrinsics& k, int csr,
                const Eigen::Vector3i& corner = Eigen::Vector3i::Zero()) {
  sb::ThreadPool pool(2);
  sb::CpuBackend surface(config(0), k, pool), carving(config(1), k, pool);
  sb::StageTimes times;
  for (sb::CpuBackend* b : {&surface, &carving}) {
    if (corner != Eigen::Vector3i::Zero()) b->moveVolume(corner);
    b->preprocess(raw, float(1.0 / kRoomDepthScale), csr, times);
    b->integrate(pose.cast<float>(), times);
  }
  const std::vector<int16_t> s = logical(surface), c = logical(carving);
  Outcome o;
  size_t wrong = 0;
  for (size_t i = 0; i < s.size(); i += 2) {
    o.band += c[i] < 32767;
    if (s[i] == c[i] && s[i + 1] == c[i + 1]) continue;
    if (c[i] == 32767 && c[i + 1] == 1 && s[i] == 32767 && s[i + 1] == 0)
      ++o.carvedOnly;
    else
      ++wrong;
  }
  CHECK(wrong == 0);
  CHECK(times.work.integrateBlocks > 0);
  return o;
}

sb::DepthRaw constantDepth(const sb::Intrinsics& k, double metres) {
  sb::DepthRaw raw(k.width, k.height);
  for (size_t p = 0; p < raw.size(); ++p) raw.pixels()[p] = static_cast<uint16_t>(metres * kRoomDepthScale);
  return raw;
}

Eigen::Isometry3d at(double x, double y, double z) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, y, z);
  return pose;
}

}  // namespace

TEST_CASE("surface blocks: a plane's band is integrated exactly, free space is not carved", "[pipeline][integrate]") {
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  const int csr = GENERATE(1, 2, 4);
  const Outcome o = compare(constantDepth(k, 1.5), at(1.6, 1.6, 0.2), k, csr);
  CHECK(o.band > 1000);
  CHECK(o.carvedOnly > 1000);
}

TEST_CASE("surface blocks: a corner of the room, tilted, with holes", "[pipeline][integrate]") {
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  const sb::test::Room room;
  Eigen::Isometry3d pose = at(1.5, 1.5, 0.9) * sb::test::motion({0, 0, 0}, 35.0, {0.3, 1, 0.1});
  sb::DepthRaw raw = sb::test::renderRoom(room, pose, k).depth;
  for (size_t p = 0; p < raw.size(); p += 23) raw.pixels()[p] = 0;
  const Outcome o = compare(raw, pose, k, GENERATE(1, 2));
  CHECK(o.band > 1000);
}

TEST_CASE("surface blocks: an empty frame lists no block", "[pipeline][integrate]") {
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  sb::SurfaceBlocks blocks;
  const std::vector<float> depth(size_t(k.width) * k.height, 0.0f);
  blocks.build(depth.data(), k.width, k.height, sb::toCamera(k), sb::toMat34(at(1.6, 1.6, 0.2).cast<float>().matrix()),
               kRes, kSize / kRes, 0.1f, 8);
  CHECK(blocks.blocks().empty());
  sb::ThreadPool pool(1);
  sb::CpuBackend surface(config(0), k, pool);
  sb::StageTimes times;
  surface.preprocess(sb::DepthRaw(k.width, k.height), float(1.0 / kRoomDepthScale), 1, times);
  surface.integrate(at(1.6, 1.6, 0.2).cast<float>(), times);
  CHECK(times.work.integrateBlocks == 0);
}

TEST_CASE("surface blocks: a plane across the volume's edge and across the moving volume's wrap",
          "[pipeline][integrate][volume_window]") {
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  // Looking along +z from near the volume's x = 0 face at a plane 0.15 m inside its far face: part of the view
  // lies outside the volume, the band reaches past it.
  const Outcome edge = compare(constantDepth(k, 2.85), at(0.3, 1.6, 0.2), k, 1);
  CHECK(edge.band > 500);
  // The same with the volume moved by 3 blocks on x and 2 on z (cyclic offset), the plane inside it.
  const Outcome wrap = compare(constantDepth(k, 1.8), at(0.9, 1.6, 0.6), k, 1, Eigen::Vector3i(24, 0, 16));
  CHECK(wrap.band > 1000);
}

TEST_CASE("ray bounds: the raycast is bit-identical with and without them, a grazed block included",
          "[pipeline][raycast]") {
  // 160 x 120 takes RayBounds' groups of kGroup^3 blocks, 320 x 240 (at least kFinePixels) its single blocks.
  const int scale = GENERATE(1, 2);
  const sb::Intrinsics k = sb::test::roomIntrinsics(160 * scale, 120 * scale);
  REQUIRE((k.width * k.height >= sb::RayBounds::kFinePixels) == (scale == 2));
  sb::ThreadPool pool(2);
  sb::CpuBackend backend(config(1), k, pool);
  sb::StageTimes times;
  // A small patch of readings: a few surface blocks in otherwise empty space.
  sb::DepthRaw raw(k.width, k.height);
  for (int y = 50 * scale; y < 58 * scale; ++y)
    for (int x = 70 * scale; x < 78 * scale; ++x)
      raw.pixels()[size_t(y) * k.width + x] = static_cast<uint16_t>(1.2 * kRoomDepthScale);
  const Eigen::Isometry3d origin = at(1.6, 1.6, 0.3);
  backend.preprocess(raw, float(1.0 / kRoomDepthScale), 1, times);
  backend.integrate(origin.cast<float>(), times);
  const sb::PipelineConfig c = config(1);
  // Views from which the patch lands on tile borders and image edges, and one sideways (grazing rays).
  size_t hits = 0, bounded = 0;
  for (const Eigen::Isometry3d& view :
       {origin, Eigen::Isometry3d(origin * sb::test::motion({0.05, 0.03, 0.0}, 3.0, {0, 1, 0})),
        Eigen::Isometry3d(origin * sb::test::motion({0.3, 0.0, 0.4}, 25.0, {0, 1, 0})),
        Eigen::Isometry3d(origin * sb::test::motion({-0.2, 0.1, 0.5}, -60.0, {0.1, 1, 0}))}) {
    const Eigen::Isometry3f posef = view.cast<float>();
    const SbMat34 pose = sb::toMat34(posef.matrix());
    std::vector<uint8_t> distance;
    // The backend's own grid through its public raycast; the kernel with and without bounds on the same grid.
    backend.raycast(posef, 1, times);
    sb::RayBounds bounds;
    // Rebuild the grid from the masks the backend keeps (pipeline/block_distance.h).
    sb::computeBlockDistance(backend.blockSurfaceMasks(), kRes >> SB_SKIP_SHIFT, distance, pool);
    bounds.compute(distance.data(), SB_SKIP_SHIFT, kRes, kSize, pose, sb::toCamera(k), k.width, k.height);
    std::vector<float> v0(3 * size_t(k.width) * k.height), n0(v0.size()), v1(v0.size()), n1(v0.size());
    for (int y = 0; y < k.height; ++y)
      for (int x = 0; x < k.width; ++x) {
        raycast(v0.data(), n0.data(), k.width, backend.volumeData(), kRes, SbVoxelOffset{}, kSize, distance.data(),
                nullptr, 0, pose, sb::toCamera(k), c.nearPlane, c.farPlane, c.raycastLargeStep * c.mu,
                c.raycastSmallStep * c.voxelSize(), c.raycastSmallStepBelow, x, y);
        raycast(v1.data(), n1.data(), k.width, backend.volumeData(), kRes, SbVoxelOffset{}, kSize, distance.data(),
                bounds.bounds().data(), bounds.columns(), pose, sb::toCamera(k), c.nearPlane, c.farPlane,
                c.raycastLargeStep * c.mu, c.raycastSmallStep * c.voxelSize(), c.raycastSmallStepBelow, x, y);
      }
    REQUIRE(std::memcmp(v0.data(), v1.data(), v0.size() * sizeof(float)) == 0);
    REQUIRE(std::memcmp(n0.data(), n1.data(), n0.size() * sizeof(float)) == 0);
    // The backend's own maps (vectorised, with its bounds) are the kernel's.
    REQUIRE(std::memcmp(v0.data(), backend.referenceVertices().data(), v0.size() * sizeof(float)) == 0);
    for (size_t p = 0; p < v0.size() / 3; ++p) hits += n0[3 * p] != SB_INVALID_NORMAL;
    for (size_t t = 0; t < bounds.bounds().size() / 2; ++t) bounded += bounds.bounds()[2 * t] > c.nearPlane;
  }
  CHECK(hits > 50);
  CHECK(bounded > 100 * size_t(scale));  // the bounds cut rays short, or this proves nothing
}
