#include "controller/pose_corrector.h"

namespace sb {

Eigen::Isometry3d nearestRigid(const Eigen::Isometry3d& t) {
  Eigen::Isometry3d r = t;
  r.linear() = Eigen::Quaterniond(t.linear()).normalized().toRotationMatrix();
  return r;
}

void CorrectionParams::read(ConfigReader& r) {
  r.number("correction_velocity_threshold_m_per_frame", velocityThreshold, 0.0, 10.0);
  r.boolean("correction_on_tracking_failure", onTrackingFailure);
  r.integer("correction_max_extrapolated_frames", maxExtrapolatedFrames, 0, 1000);
}

void CorrectionParams::toJson(nlohmann::json& j) const {
  j["correction_velocity_threshold_m_per_frame"] = velocityThreshold;
  j["correction_on_tracking_failure"] = onTrackingFailure;
  j["correction_max_extrapolated_frames"] = maxExtrapolatedFrames;
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
    return nearestRigid(motion_ * o.previousPose);
  }
  if (!o.tracked) return std::nullopt;  // failed, correction of failures off: the pipeline keeps its pose
  if (!afterCorrection) motion_ = nearestRigid(o.pose * o.previousPose.inverse());
  correctedInARow_ = 0;
  return std::nullopt;
}

}  // namespace sb
