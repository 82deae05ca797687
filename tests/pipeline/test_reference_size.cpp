// What a frame costs when the robot's odometry carries the pose (docs/odometry.md, "adaptive on a robot"): a frame
// skipped by the tracking rate does no work at all, and the reference maps may be raycast at a coarser compute size
// than the frames tracked against them (FrameOverrides::referenceCsr).

#include <catch2/catch.hpp>
#include <cmath>

#include "core/error.h"
#include "pipeline/cpu/cpu_backend.h"
#include "pipeline/pipeline.h"
#include "tests/pipeline/synthetic_room.h"

using sb::test::kRoomDepthScale;

namespace {

struct RoomRun {
  sb::test::Room room;
  sb::Intrinsics k = sb::test::roomIntrinsics(320, 240);
  sb::ThreadPool pool{2};
  std::unique_ptr<sb::Pipeline> pipeline;
  Eigen::Isometry3d start;

  RoomRun() {
    sb::PipelineConfig c;
    c.volumeSize = 3.0f;
    c.volumeResolution = 128;
    c.bootstrapFrames = 1;
    pipeline = sb::Pipeline::createCpu(c, k, pool);
    start = pipeline->initialPose();
  }
  // The camera of frame i: a slow drift, a few millimetres and 0.3 degrees per frame.
  Eigen::Isometry3d truth(size_t i) const {
    return start * sb::test::motion({0.004 * i, -0.002 * i, 0.005 * i}, 0.3 * i, {0.2, 1.0, 0.1});
  }
  sb::DepthFrame frame(size_t i) const { return sb::test::renderRoom(room, truth(i), k, i); }
  const sb::Intrinsics& reference() { return static_cast<sb::CpuBackend&>(pipeline->backend()).referenceIntrinsics(); }
};

double angleDegrees(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / M_PI;
}

}  // namespace

TEST_CASE("a frame skipped by the tracking rate does no work", "[pipeline][knobs]") {
  RoomRun run;
  const sb::Knobs every = sb::parseKnobs("csr=1,tr=1,ir=1"), third = sb::parseKnobs("csr=1,tr=3,ir=1");
  run.pipeline->processFrame(run.frame(0), kRoomDepthScale, every);
  const sb::FrameResult skipped = run.pipeline->processFrame(run.frame(1), kRoomDepthScale, third);  // 1 % 3 != 0
  CHECK_FALSE(skipped.trackingAttempted);
  CHECK_FALSE(skipped.integrated);
  // No preprocessing, no raycast: before, a skipped frame was preprocessed for nothing (2-3 ms at 320x240).
  CHECK(skipped.times.computationMs() == 0.0);
  CHECK_FALSE(run.pipeline->processFrame(run.frame(2), kRoomDepthScale, third).trackingAttempted);
  const sb::FrameResult tracked = run.pipeline->processFrame(run.frame(3), kRoomDepthScale, third);  // 3 % 3 == 0
  REQUIRE(tracked.tracked);
  CHECK((tracked.T_camera_to_world.translation() - run.truth(3).translation()).norm() < 0.002);
}

TEST_CASE("frames track against reference maps raycast at a chosen, coarser compute size", "[pipeline][raycast]") {
  RoomRun run;
  const sb::Knobs knobs = sb::parseKnobs("csr=1,ir=1");
  run.pipeline->processFrame(run.frame(0), kRoomDepthScale, knobs);
  sb::FrameOverrides coarse;
  coarse.referenceCsr = 2;
  for (size_t i = 1; i <= 4; ++i) {
    sb::FrameResult r = run.pipeline->trackFrame(run.frame(i), kRoomDepthScale, knobs);
    INFO("frame " << i);
    REQUIRE(r.tracked);
    // The csr-1 frame pairs with the csr-2 maps as they are: no raycast before tracking (frame 1 still has the
    // bootstrap's csr-1 maps).
    CHECK(r.times[sb::Stage::raycast] == 0.0);
    CHECK((r.T_camera_to_world.translation() - run.truth(i).translation()).norm() < 0.002);
    CHECK(angleDegrees(r.T_camera_to_world, run.truth(i)) < 0.1);
    run.pipeline->finishFrame(r, std::nullopt, coarse);
    CHECK(run.reference().width == 160);
    CHECK(run.reference().height == 120);
  }
  // Finished without the choice, the maps have the frame's compute size again.
  sb::FrameResult r = run.pipeline->trackFrame(run.frame(5), kRoomDepthScale, knobs);
  run.pipeline->finishFrame(r);
  CHECK(run.reference().width == 320);
  r = run.pipeline->trackFrame(run.frame(6), kRoomDepthScale, knobs);
  coarse.referenceCsr = 3;
  CHECK_THROWS_AS(run.pipeline->finishFrame(r, std::nullopt, coarse), sb::Error);
}
