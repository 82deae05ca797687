#include "runtime/tracking_monitor.h"

namespace sb {

TrackingMonitor::TrackingMonitor(const PipelineConfig& config)
    : config_(config), encoder_(FernParams{}), relocaliser_(RelocaliserParams(config)) {}

void TrackingMonitor::resolve(Pipeline& pipeline, const DepthFrame& frame, double depthScale, FrameRecord& rec) {
  FrameResult& r = rec.result;
  Decision& d = rec.decision;
  if (!r.trackingAttempted && !recovering_) {  // bootstrap, or a frame skipped by the tracking rate
    rec.state = last_ == TrackingState::relocalised ? TrackingState::good : last_;
    return;
  }
  if (recovering_) {
    rec.relocalising = true;
    if (config_.relocalise) {
      Knobs knobs;  // DEFAULT's ICP (icp 1e-5, pd 10:5:4) at the relocaliser's compute size
      knobs.csr = config_.relocaliseCsr;
      const TryPose tryPose = [&](const Eigen::Isometry3d& start) {
        return pipeline.trackFrom(frame, depthScale, knobs, start, r);
      };
      const FernCode code = encoder_.encode(frame.depth, 1.0 / depthScale);
      rec.relocalisation = relocaliser_.relocalise(code, pipeline.pose(), tryPose);
    } else {
      rec.relocalisation.why = "relocalisation is off";
    }
    // The held pose, nothing fused, no correction; the next frame's ICP starts from this frame's final pose.
    d.correctedPose.reset();
    d.refinedPose.reset();
    d.integrate = false;
    d.keepReference = false;
    d.nextStartPose.reset();
    if (rec.relocalisation.accepted) {
      pipeline.adoptAttempt(*rec.relocalisation.attempt, r);
      recovering_ = false;
      failedInARow_ = 0;
      rec.state = last_ = TrackingState::relocalised;
    } else {
      r.tracked = false;
      rec.state = last_ = TrackingState::lost;
    }
    return;
  }
  if (r.tracked) {
    failedInARow_ = 0;
    rec.state = last_ = r.quality.known && !r.quality.constrained ? TrackingState::weak : TrackingState::good;
    return;
  }
  rec.state = last_ = TrackingState::lost;
  if (++failedInARow_ >= config_.lostAfterFailedFrames) {
    recovering_ = true;
    relocaliser_.reset();
    // From the next frame on the pose is held where this frame leaves it: no further extrapolation.
    d.nextStartPose.reset();
  }
}

void TrackingMonitor::after(const DepthFrame& frame, double depthScale, FrameRecord& rec) {
  if (rec.state == TrackingState::good && rec.result.trackingAttempted && !rec.result.poseOverridden &&
      config_.relocalise) {
    const FernCode code = encoder_.encode(frame.depth, 1.0 / depthScale);
    rec.keyframeAdded = relocaliser_.harvest(code, rec.result.T_camera_to_world, rec.result.frame);
    relocaliser_.noteTracked(rec.result.pairAgreement);
  }
  rec.keyframes = relocaliser_.keyframes().size();
}

}  // namespace sb
