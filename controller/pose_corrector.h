#pragma once
// Pose correction (architecture.md D4): when the tracked velocity jumps above a threshold or tracking failed,
// the frame's pose is replaced by constant-velocity extrapolation of the full rigid motion,
// Pose_t = T_{t-1} * Pose_{t-1}, and the motion is kept (T_t = T_{t-1}); otherwise T_t = Pose_t * Pose_{t-1}^-1.
// Motions are in the world (volume) frame.
// Right after a corrected frame, Pose_{t-1} is an extrapolation: a tracked frame's velocity against it measures
// the extrapolation's error, not a glitch, so that frame is accepted without the jump test and its apparent
// motion is not learnt (else one wrong correction feeds the next: seen on the blank-wall stress sequence,
// where 423 frames in a row were corrected and the trajectory ran off by a metre).

#include <Eigen/Geometry>
#include <optional>

#include "core/config_reader.h"
#include "controller/controller.h"

namespace sb {

// T with its rotation replaced by the nearest rotation (through the normalised quaternion). Isometry3d's
// inverse() transposes the rotation, so a motion learnt from poses with rounding error carries about twice
// their error, and a pose extrapolated with it three times: without this, repeated corrections blow the
// rotation up geometrically (a quaternion of norm 0.9987 after ~800 frames of a step run).
Eigen::Isometry3d nearestRigid(const Eigen::Isometry3d& t);

struct CorrectionParams {
  double velocityThreshold = 0.035;  // m/frame: tracked velocity above this is a tracking glitch
  bool onTrackingFailure = true;     // also correct frames whose tracking failed
  // Failed frames in a row that are extrapolated; later ones keep the previous pose (SLAMBench's behaviour on a
  // failed track), so a camera that stays lost does not fly off at the last velocity.
  int maxExtrapolatedFrames = 5;

  // Keys: correction_velocity_threshold_m_per_frame, correction_on_tracking_failure,
  // correction_max_extrapolated_frames.
  void read(ConfigReader& reader);
  void toJson(nlohmann::json& section) const;  // adds the same keys with their values
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
  int correctedInARow_ = 0;  // frames corrected since the last accepted tracked pose
};

}  // namespace sb
