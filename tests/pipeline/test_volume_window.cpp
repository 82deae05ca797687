// The moving volume (pipeline/volume_window.h, pipeline/volume_placement.h, ComputeBackend::moveVolume) on the
// CPU backend:
// - the cyclic addressing: a move copies no voxel (every voxel that stays keeps its physical address), clears
//   exactly the planes that left, and reads back through the offset what the moved window should hold;
// - a shifted volume holds, logical voxel for voxel, what a fixed volume placed where the shifted one now lies
//   holds after the same frames (the world moved instead of the volume), and its raycast (across the buffer's
//   wrap, its skipping grid moved, not rebuilt) is that volume's moved back to the world frame, bit for bit;
// - the window shifts by whole blocks once the view centre is past the threshold, and hands over the slab
//   that leaves (plus the first voxel layer that stays) before it is cleared.
// Identity rotations and dyadic positions (voxels of 1/16 m) keep every float operation of both runs exact,
// so the comparisons are bitwise.

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <vector>

#include "kernels/volume.h"
#include "pipeline/cpu/cpu_backend.h"
#include "pipeline/volume_placement.h"
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
      moving.moveVolume(Eigen::Vector3i(16, -8, 0));
      CHECK(moving.placement().cornerMetres().isApprox(corner.cast<float>()));
      // Offset (16, 56, 0): logical voxel v is stored at (v + offset) mod 64. A voxel that stays keeps its
      // physical address and content (nothing is copied); logical v now holds what logical v + (16, -8, 0) held;
      // the planes that left (physical x in [0, 16), physical y in [56, 64)) are cleared.
      const SbVoxelOffset o = moving.placement().offset();
      REQUIRE((o.x == 16 && o.y == 56 && o.z == 0));
      const int16_t* after = moving.volumeData();
      size_t checked = 0;
      for (int z = 0; z < 64; ++z)
        for (int y = 0; y < 64; ++y)
          for (int x = 0; x < 64; ++x) {
            const size_t v = size_t(sbVoxelIndex(64, o, x, y, z));
            const int sx = x + 16, sy = y - 8;
            if (sx < 64 && sy >= 0) {
              const size_t s = size_t(sx) + 64 * (size_t(sy) + 64 * size_t(z));
              checked += v == s && after[2 * v] == before[2 * s] && after[2 * v + 1] == before[2 * s + 1];
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
  // Logical voxel for voxel (the moving one read through its offset).
  const SbVoxelOffset o = moving.placement().offset();
  size_t sameVoxels = 0;
  for (int z = 0; z < 64; ++z)
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        const size_t m = size_t(sbVoxelIndex(64, o, x, y, z)), f = size_t(x) + 64 * (size_t(y) + 64 * size_t(z));
        sameVoxels += std::memcmp(moving.volumeData() + 2 * m, fixed.volumeData() + 2 * f, 4) == 0;
      }
  CHECK(sameVoxels == voxels);

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
  config.volumeShiftThreshold = 1.0f;
  config.volumeViewDistance = 1.2f;  // in front of the camera
  sb::ThreadPool pool(2);
  sb::CpuBackend backend(config, k, pool);
  integrateFrame(backend, k, at(1.5, 1.5, 0.9), Eigen::Vector3d::Zero());
  sb::VolumeWindow window(config);
  // The slabs as handed over: each copy (ComputeBackend::readVolumeBox, pieces across the wrap) against the
  // volume read voxel by voxel through the offset when it is handed over (before the move clears it).
  std::vector<sb::VolumeSlab> slabs;
  std::vector<size_t> copiedExactly;
  window.setSlabListener([&](sb::VolumeSlab&& slab) {
    const std::array<int, 3> offset = window.offset();
    const SbVoxelOffset o{offset[0], offset[1], offset[2]};
    const int16_t* volume = backend.volumeData();
    REQUIRE(slab.voxels.size() == 2 * size_t(slab.extent[0]) * slab.extent[1] * slab.extent[2]);
    size_t exact = 0, s = 0;
    for (int z = 0; z < slab.extent[2]; ++z)
      for (int y = 0; y < slab.extent[1]; ++y)
        for (int x = 0; x < slab.extent[0]; ++x, ++s) {
          const int v = sbVoxelIndex(slab.resolution, o, slab.first[0] + x, slab.first[1] + y, slab.first[2] + z);
          exact += slab.voxels[2 * s] == volume[2 * v] && slab.voxels[2 * s + 1] == volume[2 * v + 1];
        }
    copiedExactly.push_back(exact);
    slabs.push_back(std::move(slab));
  });

  // View centre (2, 2, 2): the volume centre.
  CHECK(window.follow(at(2.0, 2.0, 0.8), backend) == Eigen::Vector3i::Zero());
  // 0.9 m to the right: inside the threshold.
  CHECK(window.follow(at(2.9, 2.0, 0.8), backend) == Eigen::Vector3i::Zero());
  CHECK(slabs.empty());

  // 1.2 m to the right: 2.4 blocks of 0.5 m -> 16 voxels; the slab is voxels x in [0, 17).
  const std::vector<int16_t> before(backend.volumeData(), backend.volumeData() + 2 * size_t(64 * 64 * 64));
  CHECK(window.follow(at(3.2, 2.0, 0.8), backend) == Eigen::Vector3i(16, 0, 0));
  CHECK(window.cornerVoxels() == Eigen::Vector3i(16, 0, 0));
  CHECK(window.cornerMetres().isApprox(Eigen::Vector3d(1.0, 0.0, 0.0)));
  CHECK(window.offset() == std::array<int, 3>{16, 0, 0});
  CHECK(backend.placement().corner() == Eigen::Vector3i(16, 0, 0));
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
  CHECK(copiedExactly[0] == same);
  CHECK(observedVoxels(slab.voxels.data(), same) > 0);

  // Back to the left and down at once: two axes, two slabs, the second one from the far side.
  CHECK(window.follow(at(1.0, 3.4, 0.8), backend) == Eigen::Vector3i(-32, 24, 0));
  REQUIRE(slabs.size() == 3);
  CHECK(slabs[1].corner.isApprox(Eigen::Vector3d((16 + 64 - 33) / 16.0, 0.0, 0.0)));
  CHECK(slabs[1].extent == std::array<int, 3>{33, 64, 64});
  CHECK(slabs[2].extent == std::array<int, 3>{64, 25, 64});
  // Both read across the wrap (x from physical 47 for 33 planes; the y slab with the x offset 48).
  CHECK(copiedExactly[1] == size_t(33) * 64 * 64);
  CHECK(copiedExactly[2] == size_t(64) * 25 * 64);
  int16_t voxel[2];
  CHECK_THROWS_WITH(
      backend.readVolumeBox({60, 0, 0}, {8, 1, 1}, voxel),
      Catch::Contains("8 voxels from 60 along axis 0") && Catch::Contains("not inside the cube of 64"));
  CHECK(window.stats().shifts == 3);
  CHECK(window.offset() == std::array<int, 3>{48, 24, 0});  // (-16 mod 64, 24, 0)
}

TEST_CASE("the window's shift: whole blocks past the threshold, from the view centre or the camera", "[volume_window]") {
  sb::PipelineConfig config = smallVolume();  // 4 m, blocks of 8 voxels = 0.5 m
  config.volumeShiftThreshold = 1.0f;
  config.volumeViewDistance = 0.0f;  // the camera itself
  const sb::VolumeWindow camera(config);
  const Eigen::Vector3i corner = Eigen::Vector3i::Zero();
  CHECK(camera.shiftFor(at(2.9, 2.0, 2.0), corner) == Eigen::Vector3i::Zero());
  CHECK(camera.shiftFor(at(3.1, 2.0, 2.0), corner) == Eigen::Vector3i(16, 0, 0));   // 1.1 m: 2 blocks
  CHECK(camera.shiftFor(at(0.6, 2.0, 3.3), corner) == Eigen::Vector3i(-24, 0, 24));  // -1.4, +1.3: 3 blocks
  CHECK(camera.shiftFor(at(4.1, 2.0, 2.0), Eigen::Vector3i(16, 0, 0)) == Eigen::Vector3i(16, 0, 0));  // centre at 3 m
  // A pose 1000 m away: everything leaves, the shift is capped at one side (64 blocks), never overflows.
  CHECK(camera.shiftFor(at(1002.0, 2.0, 2.0), corner) == Eigen::Vector3i(64 * 8, 0, 0));
  Eigen::Isometry3d nan = at(2.0, 2.0, 2.0);
  nan.translation().x() = std::nan("");
  CHECK(camera.shiftFor(nan, corner) == Eigen::Vector3i::Zero());
  config.volumeViewDistance = 1.5f;  // the view centre, 1.5 m along the optical axis (+z here)
  const sb::VolumeWindow view(config);
  CHECK(view.shiftFor(at(2.0, 2.0, 2.0), corner) == Eigen::Vector3i(0, 0, 24));
  CHECK(view.shiftFor(at(2.0, 2.0, 0.5), corner) == Eigen::Vector3i::Zero());
}

TEST_CASE("VolumePlacement: offsets modulo the side and the planes a move clears", "[volume_window]") {
  sb::VolumePlacement p(64, 0.0625f);
  CHECK(!p.moved());
  CHECK(sbWrapVoxel(63, 0, 64) == 63);
  CHECK(sbWrapVoxel(40, 24, 64) == 0);
  CHECK(sbWrapVoxel(63, 63, 64) == 62);
  auto clears = p.moveTo(Eigen::Vector3i(24, 0, -8));
  REQUIRE(clears.size() == 2);
  CHECK((clears[0].axis == 0 && clears[0].first == 0 && clears[0].count == 24));
  CHECK((clears[1].axis == 2 && clears[1].first == 56 && clears[1].count == 8));  // logical [56, 64) at offset 0
  SbVoxelOffset o = p.offset();
  CHECK((o.x == 24 && o.y == 0 && o.z == 56));
  CHECK(sbVoxelIndex(64, o, 40, 0, 8) == 0);  // logical (40, 0, 8) wraps to physical (0, 0, 0)
  clears = p.moveTo(Eigen::Vector3i(32, 0, -8));
  REQUIRE(clears.size() == 1);
  CHECK((clears[0].axis == 0 && clears[0].first == 24 && clears[0].count == 8));  // logical [0, 8) at offset 24
  clears = p.moveTo(Eigen::Vector3i(32 - 1000 * 8, 0, -8));
  REQUIRE(clears.size() == 1);
  CHECK((clears[0].first == 0 && clears[0].count == 64));  // everything left
  CHECK_THROWS_WITH(p.moveTo(Eigen::Vector3i(5, 0, 0)), Catch::Contains("whole number of 8-voxel blocks"));
  // The pose in the volume frame: unchanged bit for bit while the volume never moved.
  sb::VolumePlacement fixed(64, 0.0625f);
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.translation() = Eigen::Vector3f(0.1f, -0.2f, 0.3f);
  CHECK(fixed.toVolumeFrame(pose).matrix() == pose.matrix());
}
