#pragma once
// The tracker's own evidence about one ICP result (issue 21): is this pose doubtful? A coarse result is
// doubted when
//   - tracking failed (residual or inlier test of the pipeline),
//   - the geometry barely fixes some motion (tracking quality: conditioning below a bound),
//   - ICP used every iteration at the finest level and was still moving (update norm above a bound),
//   - the inlier fraction fell far below its recent median (the view lost its overlap with the model),
//   - the tracked motion disagrees with the constant-velocity prediction by more than a hand or a robot can
//     change its motion in one frame (translation and rotation separately).
// Speed alone is never a reason: a fast motion that ICP agrees with is accepted.

#include <Eigen/Geometry>
#include <deque>
#include <string>

#include "core/config_reader.h"
#include "controller/controller.h"

namespace sb {

struct EvidenceParams {
  double maxUpdateNorm = 5e-3;           // twist norm (m, rad): ICP still moving this much after pd0 iterations
  double inlierDropRatio = 0.5;          // doubt when inliers < ratio x the recent median
  int inlierWindowFrames = 15;           // frames of the inlier median
  double predictionTranslationM = 0.03;  // m: tracked vs predicted translation per frame
  double predictionRotationDeg = 3.0;    // degrees: tracked vs predicted rotation per frame
  // Conditioning (pipeline/tracking_quality.h) below which the view is doubted as weakly constrained, read on
  // the per-pixel ICP conditioning (TrackingQuality::icpConditioning), not on the structure conditioning that
  // sets the pipeline's `constrained` flag (PipelineConfig::constrainedMinConditioning, 0.0003): the default
  // doubts a single plane, whose per-pixel value sits at the noise floor. Raising it (e.g. 0.002) also doubts views that only a
  // sliver of structure at the image edge constrains, which a coarse compute size loses first: measured on
  // stress-corridor 225 -> 82 cm ATE (still lost, like every controller there), on synth-office-traj0
  // 5.5 -> 9.5 ms/frame. 0 = never.
  double weakConditioning = 0.0006;

  // Keys: doubt_update_norm, doubt_inlier_drop_ratio, doubt_inlier_window_frames,
  // doubt_prediction_translation_m, doubt_prediction_rotation_deg, doubt_conditioning.
  void read(ConfigReader& reader);
  void toJson(nlohmann::json& section) const;  // adds the same keys with their values
};

struct Doubt {
  enum Kind { none, failed, unconstrained, notConverged, inlierDrop, prediction };  // unconstrained: weakly
  Kind kind = none;
  std::string why;  // e.g. "track failed", "unconstrained (tx)", "prediction off by 0.041 m"
  bool doubtful() const { return kind != none; }
};

// The constant-velocity prediction: this frame's pose if the last accepted motion continued.
class MotionModel {
 public:
  // The predicted pose of a frame whose previous final pose is `previousPose`.
  Eigen::Isometry3d predict(const Eigen::Isometry3d& previousPose) const;
  // Learns the motion between two accepted poses (world frame); forget() after a frame that was not tracked.
  // With the frame's tracking quality and a positive `lambda`, only as far as the view fixed each motion
  // (blendByStructure): the prior does not feed on ICP's slide along what the view leaves free.
  void learn(const Eigen::Isometry3d& previousPose, const Eigen::Isometry3d& pose,
             const TrackingQuality& quality = {}, double lambda = 0.0);
  void forget() { motion_ = Eigen::Isometry3d::Identity(); known_ = false; }
  bool known() const { return known_; }

 private:
  Eigen::Isometry3d motion_ = Eigen::Isometry3d::Identity();
  bool known_ = false;
};

class TrackingEvidence {
 public:
  explicit TrackingEvidence(const EvidenceParams& params) : params_(params) {}
  // Judges a tracking attempt against `predicted` (the motion model's pose; ignored when `usePrediction` is
  // false). Does not learn: call accept() with the frames whose result was kept.
  Doubt judge(const Observation& observation, const Eigen::Isometry3d& predicted, bool usePrediction) const;
  // The view fixes every motion well enough (conditioning at or above doubt_conditioning, or unknown).
  bool wellConstrained(const Observation& o) const {
    return !o.quality.known || o.quality.icpConditioning >= params_.weakConditioning;
  }
  // The pose is off `predicted` by more than doubt_prediction_translation_m or doubt_prediction_rotation_deg.
  bool offPrediction(const Observation& observation, const Eigen::Isometry3d& predicted) const;
  // Adds a kept frame's inlier fraction to the recent history.
  void accept(const Observation& observation);

 private:
  EvidenceParams params_;
  std::deque<double> inliers_;  // inlier fractions of recent kept frames
};

// Translation (m) and rotation (degrees) between two poses.
double translationBetween(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);
double rotationBetweenDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);

}  // namespace sb
