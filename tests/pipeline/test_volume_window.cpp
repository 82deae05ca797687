// The moving volume (pipeline/volume_window.h, ComputeBackend::shiftVolume) on the CPU backend:
// - a shifted volume holds, voxel for voxel, what a fixed volume placed where the shifted one now lies holds
//   after the same frames (the world moved instead of the volume), and its raycast is that volume's moved
//   back to the world frame, bit for bit;
// - the window shifts by whole blocks once the view centre is past the threshold, and hands over the slab
//   that leaves (plus the first voxel layer that stays) before it is cleared.
// Identity rotations and dyadic positions (voxels of 1/16 m) keep every float operation of both runs exact,
// so the comparisons are bitwise.

#include <catch2/catch.hpp>
#include <cstring>
#include <vector>

#include "pipeline/cpu/cpu_backend.h"
#include "pipeline/volume_window.h"
#include "tests/pipeline/synthetic_room.h"

namespace {

using sb::test::kRoomDepthScale;

sb::PipelineConfig smallVolume() {
  sb::PipelineConfig c;
  c.volumeResolution = 64;
  c.volumeSize = 4.0f;  // voxels of 1/16 m
  return c;
}

Eigen::Isometry3d at(double x, double y, double z) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, y, z);
  return pose;
}

// Camera positions (identity rotation, looking along +z) inside the room of synthetic_room.h.
std::vector<Eigen::Isometry3d> cameraPath() {
  std::vector<Eigen::Isometry3d> path;
  for (int i = 0; i < 6; ++i) path.push_back(at(1.5 + i / 64.0, 1.5 - i / 128.0, 0.9 + i / 64.0));
  return path;
}

void integrateFrame(sb::CpuBackend& backend, const sb::Intrinsics& k, const Eigen::Isometry3d& worldPose,
                    const Eigen::Vector3d& placeAt) {
  const sb::DepthFrame frame = sb::test::renderRoom(sb::test::Room{}, worldPose, k);
  sb::StageTimes times;
  backend.preprocess(frame.depth, float(1.0 / kRoomDepthScale), 1, times);
  Eigen::Isometry3d pose = worldPose;
  pose.translation() -= placeAt;
  backend.integrate(pose.cast<float>(), times);
}

size_t observedVoxels(const int16_t* volume, size_t voxels) {
  size_t n = 0;
  for (size_t v = 0; v < voxels; ++v) n += volume[2 * v + 1] > 0;
  return n;
}

}  // namespace

TEST_CASE("a shifted volume holds what a fixed volume placed there holds, voxel for voxel", "[volume_window]") {
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  const sb::PipelineConfig config = smallVolume();
  sb::ThreadPool pool(2);
  sb::CpuBackend moving(config, k, pool);  // corner at 0, then shifted by +16 voxels along x, -8 along y
  sb::CpuBackend fixed(config, k, pool);   // corner at (1, -0.5, 0) m from the start
  const Eigen::Vector3d corner(1.0, -0.5, 0.0);
  const std::vector<Eigen::Isometry3d> path = cameraPath();
  const size_t voxels = size_t(64) * 64 * 64;
  for (size_t i = 0; i < path.size(); ++i) {
    if (i == 3) {
      const std::vector<int16_t> before(moving.volumeData(), moving.volumeData() + 2 * voxels);
      moving.shiftVolume(0, 16, Eigen::Vector3f(1.0f, 0.0f, 0.0f));
      moving.shiftVolume(1, -8, corner.cast<float>());
      // Voxel v now holds what voxel v + (16, -8, 0) held; the voxels that came in are unobserved.
      const int16_t* after = moving.volumeData();
      size_t checked = 0;
      for (int z = 0; z < 64; ++z)
        for (int y = 0; y < 64; ++y)
          for (int x = 0; x < 64; ++x) {
            const size_t v = size_t(x) + 64 * (size_t(y) + 64 * size_t(z));
            const int sx = x + 16, sy = y - 8;
            if (sx < 64 && sy >= 0) {
              const size_t s = size_t(sx) + 64 * (size_t(sy) + 64 * size_t(z));
              checked += after[2 * v] == before[2 * s] && after[2 * v + 1] == before[2 * s + 1];
            } else {
              checked += after[2 * v] == 32767 && after[2 * v + 1] == 0;
            }
          }
      CHECK(checked == voxels);
    }
    integrateFrame(moving, k, path[i], Eigen::Vector3d::Zero());
    integrateFrame(fixed, k, path[i], corner);
  }
  const size_t observed = observedVoxels(fixed.volumeData(), voxels);
  INFO(observed << " observed voxels");
  CHECK(observed > voxels / 50);
  CHECK(std::memcmp(moving.volumeData(), fixed.volumeData(), 4 * voxels) == 0);

  // The raycast of the shifted volume (its skipping grid moved, not rebuilt) is the fixed volume's, in the world.
  sb::StageTimes times;
  const Eigen::Isometry3d view = at(1.6, 1.45, 1.0);
  Eigen::Isometry3d inFixed = view;
  inFixed.translation() -= corner;
  moving.raycast(view.cast<float>(), 1, times);
  fixed.raycast(inFixed.cast<float>(), 1, times);
  const std::vector<float>& vm = moving.referenceVertices();
  const std::vector<float>& vf = fixed.referenceVertices();
  const std::vector<float>& nm = moving.referenceNormals();
  const std::vector<float>& nf = fixed.referenceNormals();
  size_t surface = 0, same = 0;
  for (size_t p = 0; p < vm.size() / 3; ++p) {
    bool equal = true;
    for (int a = 0; a < 3; ++a) {
      equal = equal && nm[3 * p + a] == nf[3 * p + a];
      const float expected = nf[3 * p] == SB_INVALID_NORMAL ? vf[3 * p + a] : vf[3 * p + a] + float(corner[a]);
      equal = equal && vm[3 * p + a] == expected;
    }
    surface += nf[3 * p] != SB_INVALID_NORMAL;
    same += equal;
  }
  INFO(surface << " surface pixels");
  CHECK(surface > vm.size() / 3 / 2);
  CHECK(same == vm.size() / 3);
}

TEST_CASE("the volume window shifts by whole blocks past the threshold and hands over the slab", "[volume_window]") {
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  sb::PipelineConfig config = smallVolume();
  config.shiftThreshold = 0.25f;     // 1 m
  config.shiftViewDistance = 0.3f;   // 1.2 m in front of the camera
  sb::ThreadPool pool(2);
  sb::CpuBackend backend(config, k, pool);
  integrateFrame(backend, k, at(1.5, 1.5, 0.9), Eigen::Vector3d::Zero());
  sb::VolumeWindow window(config);
  std::vector<sb::VolumeSlab> slabs;
  window.setSlabListener([&](const sb::VolumeSlab& slab) { slabs.push_back(slab); });

  // View centre (2, 2, 2): the volume centre.
  CHECK(window.follow(at(2.0, 2.0, 0.8), backend) == Eigen::Vector3i::Zero());
  // 0.9 m to the right: inside the threshold.
  CHECK(window.follow(at(2.9, 2.0, 0.8), backend) == Eigen::Vector3i::Zero());
  CHECK(slabs.empty());

  // 1.2 m to the right: 2.4 blocks of 0.5 m -> 16 voxels; the slab is voxels x in [0, 17).
  const std::vector<int16_t> before(backend.volumeData(), backend.volumeData() + 2 * size_t(64 * 64 * 64));
  CHECK(window.follow(at(3.2, 2.0, 0.8), backend) == Eigen::Vector3i(16, 0, 0));
  CHECK(window.originVoxels() == Eigen::Vector3i(16, 0, 0));
  CHECK(window.origin().isApprox(Eigen::Vector3d(1.0, 0.0, 0.0)));
  REQUIRE(slabs.size() == 1);
  const sb::VolumeSlab& slab = slabs[0];
  CHECK(slab.axis == 0);
  CHECK(slab.extent == std::array<int, 3>{17, 64, 64});
  CHECK(slab.corner.isZero());
  size_t same = 0;
  for (int z = 0; z < 64; ++z)
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 17; ++x) {
        const size_t s = size_t(x) + 17 * (size_t(y) + 64 * size_t(z));
        const size_t v = size_t(x) + 64 * (size_t(y) + 64 * size_t(z));
        same += slab.voxels[2 * s] == before[2 * v] && slab.voxels[2 * s + 1] == before[2 * v + 1];
      }
  CHECK(same == size_t(17) * 64 * 64);
  CHECK(observedVoxels(slab.voxels.data(), same) > 0);

  // Back to the left and down at once: two axes, two slabs, the second one from the far side.
  CHECK(window.follow(at(1.0, 3.4, 0.8), backend) == Eigen::Vector3i(-32, 24, 0));
  REQUIRE(slabs.size() == 3);
  CHECK(slabs[1].corner.isApprox(Eigen::Vector3d((16 + 64 - 33) / 16.0, 0.0, 0.0)));
  CHECK(slabs[1].extent == std::array<int, 3>{33, 64, 64});
  CHECK(slabs[2].extent == std::array<int, 3>{64, 25, 64});
  CHECK(window.stats().shifts == 3);
}
