// Empty-space skipping on the OpenCL backend must not change what the raycast finds: two OpenCL backends, one
// skipping by the block-distance grid (kernels/raycast.h, pipeline/block_distance.h) and one not, integrate
// the same frames and must give bit-identical raycast maps from the integration pose and from moved poses.
// Then the box moves: the voxels of its old faces are seen as free space until they leave the surface band,
// so blocks that had surface lose it and their distances grow. Skipping there must still be exact (a stale
// "has surface" would only be slower; a block skipped while a voxel of it is still below the threshold would
// lose samples), checked after every integration of the moved scene.

#include <catch2/catch.hpp>
#include <cstring>
#include <string>

#include "kernels/common.h"
#include "pipeline/block_distance.h"
#include "pipeline/opencl/opencl_backend.h"
#include "tests/pipeline/synthetic_room.h"
#include "tests/pipeline/test_opencl_support.h"

using sb::test::kRoomDepthScale;

namespace {

Eigen::Isometry3d frontPose() {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() = Eigen::Vector3d(1.5, 1.5, 0.9);
  return p;
}

// Raycasts both from poses around the front pose; the maps must be equal bit for bit.
void checkSameMaps(sb::OpenClBackend& skipping, sb::OpenClBackend& plain, const std::string& when) {
  sb::StageTimes times;
  for (const Eigen::Vector3d& offset : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.15, -0.1, 0.2),
                                        Eigen::Vector3d(-0.3, 0.2, 0.5), Eigen::Vector3d(0.4, 0.3, -0.2)}) {
    for (const double yawDegrees : {0.0, -35.0}) {
      Eigen::Isometry3d pose = frontPose();
      pose.translation() += offset;
      pose.linear() =
          Eigen::AngleAxisd(yawDegrees * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
      skipping.raycast(pose.cast<float>(), 1, times);
      plain.raycast(pose.cast<float>(), 1, times);
      const std::vector<float> vs = skipping.referenceVertices(), vp = plain.referenceVertices();
      const std::vector<float> ns = skipping.referenceNormals(), np = plain.referenceNormals();
      REQUIRE(vs.size() == vp.size());
      size_t differing = 0, hits = 0;
      for (size_t i = 0; i < vs.size() / 3; ++i) {
        if (np[3 * i] != SB_INVALID_NORMAL) ++hits;
        if (std::memcmp(&vs[3 * i], &vp[3 * i], 3 * sizeof(float)) != 0 ||
            std::memcmp(&ns[3 * i], &np[3 * i], 3 * sizeof(float)) != 0)
          ++differing;
      }
      INFO(when << ", offset " << offset.transpose() << ", yaw " << yawDegrees << ": " << differing << " of "
                << vs.size() / 3 << " pixels differ, " << hits << " hit a surface");
      CHECK(differing == 0);
      CHECK(hits > vs.size() / 3 / 5);
    }
  }
}

// Voxels of the half-open box [lo, hi) (voxel indices) whose tsdf is below the skipping threshold.
size_t surfaceVoxels(const int16_t* volume, int resolution, const Eigen::Vector3i& lo,
                     const Eigen::Vector3i& hi, int16_t below) {
  size_t n = 0;
  for (int z = lo.z(); z < hi.z(); ++z)
    for (int y = lo.y(); y < hi.y(); ++y)
      for (int x = lo.x(); x < hi.x(); ++x)
        if (volume[2 * (x + (size_t(y) + size_t(z) * resolution) * resolution)] < below) ++n;
  return n;
}

}  // namespace

TEST_CASE(
    "OpenCL raycast finds the same surface with and without empty-space skipping, also after the scene "
    "changes",
    "[opencl][raycast]") {
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  sb::PipelineConfig config;
  config.volumeSize = 3.0f;
  config.volumeResolution = 128;
  config.backend = sb::BackendKind::opencl;
  config.maxWeight = 2;  // old surface leaves the band within a few integrations
  // The moved box's old face is cleared by carving free space (every integration carves).
  sb::OpenClBackend skipping(config, k, sb::test::openclTestDevice());
  config.emptySpaceSkipping = false;
  sb::OpenClBackend plain(config, k, sb::test::openclTestDevice());
  sb::StageTimes times;
  const auto integrateBoth = [&](const sb::test::Room& room, const Eigen::Isometry3d& view) {
    const sb::DepthRaw raw = sb::test::renderRoom(room, view, k).depth;
    for (sb::OpenClBackend* b : {&skipping, &plain}) {
      b->preprocess(raw, float(1.0 / kRoomDepthScale), 1, times);
      b->integrate(view.cast<float>(), times);
    }
  };
  // Before any integration: an empty volume, no ray hits anything, with or without skipping.
  skipping.raycast(frontPose().cast<float>(), 1, times);
  plain.raycast(frontPose().cast<float>(), 1, times);
  CHECK(skipping.referenceNormals() == plain.referenceNormals());

  const sb::test::Room before;
  for (int i = 0; i < 2; ++i) integrateBoth(before, frontPose());
  checkSameMaps(skipping, plain, "box at its first place");

  // The box moves 0.6 m along x; its old front face (z = 1.9 m) is now seen through as free space (the box
  // of voxels below keeps 5 cm away from the floor's band).
  sb::test::Room after = before;
  after.boxMin.x() += 0.6;
  after.boxMax.x() += 0.6;
  const float voxelsPerMetre = config.volumeResolution / config.volumeSize;
  const Eigen::Vector3i lo = (Eigen::Vector3d(1.05, 1.55, 1.8) * voxelsPerMetre).cast<int>();
  const Eigen::Vector3i hi = (Eigen::Vector3d(1.3, 1.85, 2.0) * voxelsPerMetre).cast<int>();
  const int16_t below = sb::surfaceTsdfBelow(config.raycastSmallStepBelow);
  const size_t oldFace = surfaceVoxels(plain.volumeData(), config.volumeResolution, lo, hi, below);
  INFO(oldFace << " voxels of the old front face below the threshold before the move");
  REQUIRE(oldFace > 100);
  const int integrations = 8;
  for (int i = 0; i < integrations; ++i) {
    integrateBoth(after, frontPose());
    checkSameMaps(skipping, plain, "integration " + std::to_string(i + 1) + " after the move");
  }
  // The old face must really have left the surface band, or this test proves nothing about emptied blocks.
  const size_t left = surfaceVoxels(plain.volumeData(), config.volumeResolution, lo, hi, below);
  INFO(left << " of them still below it after " << integrations << " integrations");
  CHECK(left < oldFace / 10);
}
