// The tracking state's rule on a tracked frame's agreement with the map (runtime/tracking_monitor.h; issue 53
// finding 7): a depth-only kidnap to a look-alike stretch of corridor tracked at the old pose with its pair
// agreement at 0.26-0.28 where the frames before had 0.70-0.82, the model covering as much of the view as
// before, and was called good. Such a frame is weak and not fused, and a run of them hands over to the
// relocaliser; a frame that sees what the model does not hold yet, or agrees within a drive's spread, stays good.

#include <catch2/catch.hpp>

#include "odometry/motion_model.h"
#include "runtime/tracking_monitor.h"
#include "tests/pipeline/synthetic_room.h"

namespace {

struct Monitored {
  sb::PipelineConfig config;
  sb::ThreadPool pool{1};
  std::unique_ptr<sb::Pipeline> pipeline;
  std::unique_ptr<sb::TrackingMonitor> monitor;
  sb::odometry::MotionModel model{sb::odometry::OdometryConfig{}};  // no odometry: no wheels to weigh
  size_t frames = 0;

  Monitored() {
    config.volumeSize = 3.0f;
    config.volumeResolution = 32;
    pipeline = sb::Pipeline::createCpu(config, sb::test::roomIntrinsics(160, 120), pool);
    monitor = std::make_unique<sb::TrackingMonitor>(config);
  }

  // A frame tracked by the pipeline's tests (and well constrained) with this pair agreement (the share of the
  // model's pairs it agrees with) and inlier fraction (per pixel: agreement times the model's coverage), the
  // controller asking to fuse it.
  sb::FrameRecord track(double agreement, double inliers) {
    sb::FrameRecord rec;
    sb::FrameResult& r = rec.result;
    r.frame = ++frames;
    r.timestamp = static_cast<double>(frames) / 30.0;
    r.trackingAttempted = r.tracked = true;
    r.pairAgreement = agreement;
    r.inlierFraction = inliers;
    r.modelCoverage = inliers / agreement;
    r.quality.known = true;
    r.quality.constrained = true;
    rec.decision.integrate = true;
    const sb::odometry::FrameMotion motion;  // no previous frame: the platform's physics is not asked
    monitor->resolve(*pipeline, sb::DepthFrame{}, 1000.0, rec, model, motion);
    return rec;
  }
};

}  // namespace

TEST_CASE("a tracked frame whose view does not fit the map where the model covers it is not good",
          "[runtime][tracking_state]") {
  Monitored m;
  // A drive's frames: agreement 0.75, the model covering 0.6 of the view.
  for (int i = 0; i < 30; ++i) REQUIRE(m.track(0.75, 0.45).state == sb::TrackingState::good);

  SECTION("a drive's spread and a view of what the model does not hold yet stay good and fused") {
    const sb::FrameRecord spread = m.track(0.45, 0.27);  // 0.6 of the median, as much of it covered
    CHECK(spread.state == sb::TrackingState::good);
    CHECK(spread.decision.integrate == true);
    const sb::FrameRecord unmapped = m.track(0.3, 0.06);  // a stretch the volume has not mapped: coverage 0.2
    CHECK(unmapped.state == sb::TrackingState::good);
    CHECK(unmapped.decision.integrate == true);
    CHECK_FALSE(m.monitor->recovering());
  }

  SECTION("a view in the wrong place is weak, not fused, and a run of them hands over to the relocaliser") {
    // The look-alike stretch: agreement 0.28, the model covering as much of the view as before.
    const sb::FrameRecord first = m.track(0.28, 0.17);
    CHECK(first.state == sb::TrackingState::weak);
    CHECK(first.decision.integrate == false);
    CHECK(first.decision.keepReference);
    CHECK_FALSE(m.monitor->recovering());
    for (int i = 1; i < m.config.lostAfterFailedFrames; ++i) {
      INFO("wrong-place frame " << i + 1 << " of " << m.config.lostAfterFailedFrames);
      CHECK_FALSE(m.monitor->recovering());  // these frames do not lower the bar: it is the good frames'
      const sb::FrameRecord next = m.track(0.28, 0.17);
      CHECK(next.state == sb::TrackingState::weak);
      CHECK(next.decision.integrate == false);
    }
    CHECK(m.monitor->recovering());
  }

  SECTION("a view that agrees with almost none of a model covering it in part is not good either") {
    // The model covering 0.45 of the view (under 0.8 of the usual 0.6) and the view agreeing with 5% of it: the
    // pairs it contradicts alone cover more than half of what the model usually does (it was good and fused).
    const sb::FrameRecord contradicted = m.track(0.05, 0.0225);
    CHECK(contradicted.state == sb::TrackingState::weak);
    CHECK(contradicted.decision.integrate == false);
  }

  SECTION("one such frame between good ones is weak alone") {
    CHECK(m.track(0.28, 0.17).state == sb::TrackingState::weak);
    CHECK(m.track(0.75, 0.45).state == sb::TrackingState::good);
    for (int i = 1; i < m.config.lostAfterFailedFrames; ++i) m.track(0.28, 0.17);
    CHECK_FALSE(m.monitor->recovering());  // the good frame between ended the run
  }
}
