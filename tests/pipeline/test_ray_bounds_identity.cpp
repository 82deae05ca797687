// The raycast's ray bounds (pipeline/ray_bounds.h) leave its maps bit-identical to the march without them
// (issue 43; the bounds against their definition, by brute force: test_ray_bounds.cpp).

#include <catch2/catch.hpp>
#include <cstring>
#include <vector>

#include "kernels/raycast.h"
#include "pipeline/block_distance.h"
#include "pipeline/cpu/cpu_backend.h"
#include "pipeline/kernel_args.h"
#include "pipeline/ray_bounds.h"
#include "tests/pipeline/synthetic_room.h"

namespace {

using sb::test::kRoomDepthScale;

constexpr int kRes = 64;
constexpr float kSize = 3.2f;

sb::PipelineConfig config() {
  sb::PipelineConfig c;
  c.volumeResolution = kRes;
  c.volumeSize = kSize;
  return c;
}

Eigen::Isometry3d at(double x, double y, double z) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, y, z);
  return pose;
}

}  // namespace

TEST_CASE("ray bounds: the raycast is bit-identical with and without them, a grazed block included",
          "[pipeline][raycast]") {
  // 160 x 120 takes RayBounds' groups of kGroup^3 blocks, 320 x 240 (at least kFinePixels) its single blocks.
  const int scale = GENERATE(1, 2);
  const sb::Intrinsics k = sb::test::roomIntrinsics(160 * scale, 120 * scale);
  REQUIRE((k.width * k.height >= sb::RayBounds::kFinePixels) == (scale == 2));
  sb::ThreadPool pool(2);
  sb::CpuBackend backend(config(), k, pool);
  sb::StageTimes times;
  // A small patch of readings: a few surface blocks in otherwise empty space.
  sb::DepthRaw raw(k.width, k.height);
  for (int y = 50 * scale; y < 58 * scale; ++y)
    for (int x = 70 * scale; x < 78 * scale; ++x)
      raw.pixels()[size_t(y) * k.width + x] = static_cast<uint16_t>(1.2 * kRoomDepthScale);
  const Eigen::Isometry3d origin = at(1.6, 1.6, 0.3);
  backend.preprocess(raw, float(1.0 / kRoomDepthScale), 1, times);
  backend.integrate(origin.cast<float>(), times);
  const sb::PipelineConfig c = config();
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
