// The pipeline on analytic scenes: ICP recovers a known motion, integrate + raycast returns the surface,
// knobs change between frames, results are independent of the thread count, a model rendered from another
// viewpoint leaves tracking unchanged.

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "core/error.h"
#include "kernels/common.h"
#include "pipeline/cpu/cpu_backend.h"
#include "pipeline/pipeline.h"
#include "tests/pipeline/synthetic_room.h"

using sb::test::kRoomDepthScale;

namespace {

sb::PipelineConfig roomConfig(int resolution) {
  sb::PipelineConfig c;
  c.volumeSize = 3.0f;
  c.volumeResolution = resolution;
  c.bootstrapFrames = 1;
  return c;
}

double angleDegrees(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / M_PI;
}

}  // namespace

TEST_CASE("ICP recovers a known rigid motion between two frames to 1 mm / 0.1 degree", "[pipeline][track]") {
  const sb::test::Room room;
  const sb::Intrinsics k = sb::test::roomIntrinsics(320, 240);
  sb::PipelineConfig config = roomConfig(256);
  sb::ThreadPool pool(2);
  auto pipeline = sb::Pipeline::createCpu(config, k, pool);
  sb::Knobs knobs = sb::knobPreset("accurate");
  const Eigen::Isometry3d start = pipeline->initialPose();
  pipeline->processFrame(sb::test::renderRoom(room, start, k, 0), kRoomDepthScale, knobs);
  // A fast inter-frame motion in the camera frame: 2.7 cm and 1.5 degrees.
  const Eigen::Isometry3d truth = start * sb::test::motion({0.02, -0.01, 0.015}, 1.5, {0.3, 1.0, -0.2});
  sb::FrameResult r = pipeline->processFrame(sb::test::renderRoom(room, truth, k, 1), kRoomDepthScale, knobs);
  REQUIRE(r.trackingAttempted);
  CHECK(r.tracked);
  CHECK(r.inlierFraction > 0.5);
  CHECK(r.residual < 0.002);
  const double error = (r.T_camera_to_world.translation() - truth.translation()).norm();
  INFO("translation error " << error * 1000 << " mm, rotation error " << angleDegrees(r.T_camera_to_world, truth) << " deg");
  CHECK(error < 0.001);
  CHECK(angleDegrees(r.T_camera_to_world, truth) < 0.1);
  CHECK(r.velocity == Approx((truth.translation() - start.translation()).norm()).margin(0.001));
}

TEST_CASE("integrating a plane then raycasting returns the plane", "[pipeline][integrate][raycast]") {
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  sb::PipelineConfig config = roomConfig(128);  // 2.34 cm voxels
  sb::ThreadPool pool(2);
  sb::CpuBackend backend(config, k, pool);
  const double wallDepth = 1.237;
  sb::DepthRaw raw(k.width, k.height, static_cast<uint16_t>(std::lround(wallDepth * kRoomDepthScale)));
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.translation() = Eigen::Vector3f(1.5f, 1.5f, 0.9f);
  sb::StageTimes times;
  backend.preprocess(raw, float(1.0 / kRoomDepthScale), 1, times);
  backend.integrate(pose, times);
  backend.raycast(pose, 1, times);
  const auto& v = backend.referenceVertices();
  const auto& n = backend.referenceNormals();
  const double voxel = config.voxelSize();
  int valid = 0;
  // Pixels near the image border see voxels at the frustum's edge, whose unobserved neighbours bend the
  // surface (as in every KinectFusion); the interior must be exact.
  const int margin = 4;
  for (int i = 0; i < k.width * k.height; ++i) {
    const int x = i % k.width, y = i / k.width;
    if (x < margin || y < margin || x >= k.width - margin || y >= k.height - margin) continue;
    REQUIRE(n[3 * i] != SB_INVALID_NORMAL);
    ++valid;
    CHECK(std::fabs(v[3 * i + 2] - (0.9 + wallDepth)) < 0.1 * voxel);
    CHECK(n[3 * i + 2] == Approx(-1.0).margin(1e-3));
  }
  CHECK(valid == (k.width - 2 * margin) * (k.height - 2 * margin));
  CHECK(times[sb::Stage::integrate] > 0);
  CHECK(times[sb::Stage::raycast] > 0);
  // The same with empty-space skipping off: the same surface (skipping only leaves out samples that cannot
  // change the march; test_raycast_skip.cpp covers harder scenes).
  config.emptySpaceSkipping = false;
  sb::CpuBackend plain(config, k, pool);
  plain.preprocess(raw, float(1.0 / kRoomDepthScale), 1, times);
  plain.integrate(pose, times);
  plain.raycast(pose, 1, times);
  for (int i = 0; i < k.width * k.height; ++i) {
    const int x = i % k.width, y = i / k.width;
    if (x < margin || y < margin || x >= k.width - margin || y >= k.height - margin) continue;
    CHECK(plain.referenceVertices()[3 * i + 2] == v[3 * i + 2]);
  }
}

namespace {

// A short moving-camera sequence through the room; returns the final poses.
std::vector<Eigen::Isometry3d> runRoom(sb::ThreadPool& pool, const std::vector<sb::Knobs>& knobs,
                                       std::vector<sb::FrameResult>* results = nullptr) {
  const sb::test::Room room;
  const sb::Intrinsics k = sb::test::roomIntrinsics(320, 240);
  auto pipeline = sb::Pipeline::createCpu(roomConfig(128), k, pool);
  std::vector<Eigen::Isometry3d> poses;
  const Eigen::Isometry3d start = pipeline->initialPose();
  for (size_t i = 0; i < knobs.size(); ++i) {
    const Eigen::Isometry3d truth = start * sb::test::motion({0.008 * i, -0.004 * i, 0.006 * i}, 0.5 * i, {0.2, 1.0, 0.1});
    sb::FrameResult r = pipeline->processFrame(sb::test::renderRoom(room, truth, k, i), kRoomDepthScale, knobs[i]);
    poses.push_back(r.T_camera_to_world);
    if (results) results->push_back(r);
    INFO("frame " << i << " error " << (r.T_camera_to_world.translation() - truth.translation()).norm());
    // Coarse compute sizes track (and integrate) less precisely: 1 cm, 4 mm * csr at csr 4 and 8 (a 40x30 image).
    if (r.tracked) CHECK((r.T_camera_to_world.translation() - truth.translation()).norm() < std::max(0.01, 0.004 * knobs[i].csr));
  }
  return poses;
}

}  // namespace

TEST_CASE("knobs may change between any two frames, csr included", "[pipeline][knobs]") {
  sb::ThreadPool pool(2);
  std::vector<sb::Knobs> knobs;
  for (const char* text : {"csr=1", "csr=1", "csr=2", "csr=4,icp=1e-4,pd=6:5:4", "csr=8", "csr=1,ir=1", "csr=2,tr=4",
                           "csr=2,tr=1"})
    knobs.push_back(sb::parseKnobs(text));
  std::vector<sb::FrameResult> results;
  runRoom(pool, knobs, &results);
  for (size_t i = 0; i < results.size(); ++i) {
    CHECK(results[i].knobs == knobs[i]);
    if (i >= 1 && i != 6) CHECK(results[i].tracked);
  }
  // tr=4 on frame 6 (6 % 4 != 0): no tracking, the pose stays, nothing is integrated.
  CHECK_FALSE(results[6].trackingAttempted);
  CHECK_FALSE(results[6].integrated);
  CHECK(results[6].T_camera_to_world.matrix() == results[5].T_camera_to_world.matrix());
  CHECK(results[5].integrated);  // ir=1
  CHECK_FALSE(results[3].integrated);  // ir=2 (default) on an odd frame
}

TEST_CASE("the trajectory is bit-identical for 1 and 2 threads", "[pipeline][determinism]") {
  std::vector<sb::Knobs> knobs(5, sb::knobPreset("default"));
  knobs[3].csr = 2;
  sb::ThreadPool one(1), two(2);
  const auto a = runRoom(one, knobs);
  const auto b = runRoom(two, knobs);
  REQUIRE(a.size() == b.size());
  for (size_t i = 0; i < a.size(); ++i) CHECK(a[i].matrix() == b[i].matrix());
}

TEST_CASE("pose override replaces the pose used downstream", "[pipeline]") {
  const sb::test::Room room;
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  sb::ThreadPool pool(2);
  auto pipeline = sb::Pipeline::createCpu(roomConfig(64), k, pool);
  const sb::Knobs knobs;
  pipeline->processFrame(sb::test::renderRoom(room, pipeline->initialPose(), k, 0), kRoomDepthScale, knobs);
  sb::FrameResult r = pipeline->trackFrame(sb::test::renderRoom(room, pipeline->initialPose(), k, 1), kRoomDepthScale, knobs);
  CHECK_THROWS_AS(pipeline->trackFrame(sb::test::renderRoom(room, pipeline->initialPose(), k, 2), kRoomDepthScale, knobs),
                  sb::Error);
  Eigen::Isometry3d corrected = pipeline->initialPose();
  corrected.translation().x() += 0.01;
  pipeline->finishFrame(r, corrected);
  CHECK(r.poseOverridden);
  CHECK(r.T_camera_to_world.matrix() == corrected.matrix());
  CHECK(pipeline->pose().matrix() == corrected.matrix());
  CHECK(r.velocity == Approx(0.01));
}

TEST_CASE("a model rendered from another viewpoint leaves the next frames' tracking unchanged",
          "[pipeline][render]") {
  const sb::test::Room room;
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  sb::ThreadPool pool(2);
  auto plain = sb::Pipeline::createCpu(roomConfig(64), k, pool);
  auto viewed = sb::Pipeline::createCpu(roomConfig(64), k, pool);
  const sb::Knobs knobs;
  Eigen::Isometry3d above = plain->initialPose();
  above.translation().y() -= 0.5;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Isometry3d truth =
        plain->initialPose() * sb::test::motion({0.01 * i, 0.0, 0.005 * i}, 0.5 * i, {0.0, 1.0, 0.0});
    const sb::DepthFrame frame = sb::test::renderRoom(room, truth, k, static_cast<size_t>(i));
    const sb::FrameResult a = plain->processFrame(frame, kRoomDepthScale, knobs);
    const sb::FrameResult b = viewed->processFrame(frame, kRoomDepthScale, knobs);
    INFO("frame " << i);
    CHECK(a.T_camera_to_world.matrix() == b.T_camera_to_world.matrix());
    if (i == 1) {
      const sb::Image<uint8_t> fromAbove = viewed->renderModel(above, 1);
      const sb::Image<uint8_t> fromPose = viewed->renderModel(1);
      CHECK(fromAbove.width() == 160);
      const size_t pixels = static_cast<size_t>(fromAbove.width()) * static_cast<size_t>(fromAbove.height());
      CHECK_FALSE(std::equal(fromAbove.data(), fromAbove.data() + pixels, fromPose.data()));
      viewed->renderModel(above, 2);  // the last render leaves maps of another view and size behind
    }
  }
}

TEST_CASE("bad frames and knobs are rejected with sb::Error", "[pipeline]") {
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  sb::ThreadPool pool(1);
  auto pipeline = sb::Pipeline::createCpu(roomConfig(64), k, pool);
  sb::DepthFrame wrong;
  wrong.depth = sb::DepthRaw(100, 100);
  CHECK_THROWS_WITH(pipeline->processFrame(wrong, 1000, sb::Knobs{}), Catch::Contains("100x100"));
  sb::Knobs bad;
  bad.csr = 3;
  sb::DepthFrame ok;
  ok.depth = sb::DepthRaw(k.width, k.height);
  CHECK_THROWS_WITH(pipeline->processFrame(ok, 1000, bad), Catch::Contains("csr=3"));
  const sb::Intrinsics tiny = sb::test::roomIntrinsics(64, 48);
  auto small = sb::Pipeline::createCpu(roomConfig(64), tiny, pool);
  sb::Knobs tooSmall;
  tooSmall.csr = 8;  // 8x6 at csr 8 -> 2x1 at the coarsest level
  sb::DepthFrame tinyFrame;
  tinyFrame.depth = sb::DepthRaw(tiny.width, tiny.height);
  CHECK_THROWS_WITH(small->processFrame(tinyFrame, 1000, tooSmall), Catch::Contains("too small"));
}
