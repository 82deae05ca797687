#include "controller/pose_corrector.h"

namespace sb {

void CorrectionParams::read(ConfigReader& r) {
  r.number("correction_velocity_threshold_m_per_frame", velocityThreshold, 0.0, 10.0);
  r.boolean("correction_on_tracking_failure", onTrackingFailure);
}

std::optional<Eigen::Isometry3d> PoseCorrector::correct(const Observation& o) {
  if (!o.trackingAttempted) return std::nullopt;
  const bool jump = o.velocity > params_.velocityThreshold;
  const bool failed = !o.tracked && params_.onTrackingFailure;
  if (jump || failed) return motion_ * o.previousPose;
  motion_ = o.pose * o.previousPose.inverse();
  return std::nullopt;
}

}  // namespace sb
