#include "controller/pose_corrector.h"

namespace sb {

namespace {

// T with its rotation replaced by the nearest rotation (through the normalised quaternion). Isometry3d's
// inverse() transposes the rotation, so a motion learnt from poses with rounding error carries about twice
// their error, and a pose extrapolated with it three times: without this, repeated corrections blow the
// rotation up geometrically (a quaternion of norm 0.9987 after ~800 frames of a step run).
Eigen::Isometry3d rigid(const Eigen::Isometry3d& t) {
  Eigen::Isometry3d r = t;
  r.linear() = Eigen::Quaterniond(t.linear()).normalized().toRotationMatrix();
  return r;
}

}  // namespace

void CorrectionParams::read(ConfigReader& r) {
  r.number("correction_velocity_threshold_m_per_frame", velocityThreshold, 0.0, 10.0);
  r.boolean("correction_on_tracking_failure", onTrackingFailure);
  r.integer("correction_max_extrapolated_frames", maxExtrapolatedFrames, 0, 1000);
}

std::optional<Eigen::Isometry3d> PoseCorrector::correct(const Observation& o) {
  if (!o.trackingAttempted) return std::nullopt;
  const bool afterCorrection = correctedInARow_ > 0;
  const bool jump = o.tracked && !afterCorrection && o.velocity > params_.velocityThreshold;
  const bool failed = !o.tracked && params_.onTrackingFailure;
  if (failed && correctedInARow_ >= params_.maxExtrapolatedFrames) {
    ++correctedInARow_;
    return o.previousPose;  // lost for too long: hold the pose
  }
  if (jump || failed) {
    ++correctedInARow_;
    return rigid(motion_ * o.previousPose);
  }
  if (!o.tracked) return std::nullopt;  // failed, correction of failures off: the pipeline keeps its pose
  if (!afterCorrection) motion_ = rigid(o.pose * o.previousPose.inverse());
  correctedInARow_ = 0;
  return std::nullopt;
}

}  // namespace sb
