#pragma once
// Pose correction (DESIGN section 4): when the tracked velocity jumps above a threshold or tracking failed,
// the frame's pose is replaced by constant-velocity extrapolation of the full rigid motion,
// Pose_t = T_{t-1} * Pose_{t-1}, and the motion is kept (T_t = T_{t-1}); otherwise T_t = Pose_t * Pose_{t-1}^-1.
// Motions are in the world (volume) frame.

#include <Eigen/Geometry>
#include <optional>

#include "controller/config_reader.h"
#include "controller/controller.h"

namespace sb {

struct CorrectionParams {
  double velocityThreshold = 0.035;  // m/frame: tracked velocity above this is a tracking glitch
  bool onTrackingFailure = true;     // also correct frames whose tracking failed

  // Keys: correction_velocity_threshold_m_per_frame, correction_on_tracking_failure.
  void read(ConfigReader& reader);
};

class PoseCorrector {
 public:
  explicit PoseCorrector(const CorrectionParams& params) : params_(params) {}
  // The corrected pose for this frame, or nullopt to keep the tracked one. Frames without a tracking attempt
  // are never corrected and do not change the motion.
  std::optional<Eigen::Isometry3d> correct(const Observation& observation);
  const Eigen::Isometry3d& motion() const { return motion_; }

 private:
  CorrectionParams params_;
  Eigen::Isometry3d motion_ = Eigen::Isometry3d::Identity();  // T_{t-1}, world frame
};

}  // namespace sb
