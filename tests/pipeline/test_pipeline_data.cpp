// The pipeline on real data (tagged [data]: reads ../shared/data).

#include <catch2/catch.hpp>

#include "core/trajectory.h"
#include "drivers/sequence.h"
#include "eval/trajectory_eval.h"
#include "pipeline/pipeline.h"
#include "tests/support/test_data.h"

TEST_CASE("7-Scenes redkitchen, first 150 frames at DEFAULT knobs", "[data][pipeline]") {
  sb::SequenceOptions options;
  options.maxFrames = 150;
  auto source = sb::openSequence(sb::test::sharedDataDir() + "/7scenes-redkitchen-a", options);
  const sb::SequenceInfo info = source->info();
  sb::PipelineConfig config;  // 5 m, 256^3, camera at (0.5, 0.5, 0.3): the setup
  auto pipeline = sb::Pipeline::createCpu(config, info.intrinsics);
  const sb::Knobs knobs = sb::knobPreset("default");
  sb::Trajectory trajectory;
  size_t attempted = 0, tracked = 0;
  while (auto frame = source->next()) {
    const sb::FrameResult r = pipeline->processFrame(*frame, info.depthScale, knobs);
    trajectory.push_back({r.timestamp, r.T_camera_to_world});
    attempted += r.trackingAttempted;
    tracked += r.tracked;
  }
  REQUIRE(trajectory.size() == 150);
  const sb::AteResult ate = sb::computeAte(trajectory, sb::readTumTrajectory(info.groundTruthPath));
  INFO("ATE rmse " << ate.rmse * 100 << " cm, tracked " << tracked << "/" << attempted);
  CHECK(tracked == attempted);
  CHECK(ate.rmse < 0.03);
}
