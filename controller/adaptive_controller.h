#pragma once
// `adaptive`: the product's controller (issue 21; architecture.md D4, beyond the paper). It decides from the
// tracker's own evidence, not from speed:
//   1. run at the coarsest level the evidence allows: from the finest, after the bootstrap, one level coarser every
//      `relax_frames` frames without doubt, up to the ladder's max_level (max_level_with_odometry while the
//      robot's odometry drives the frames: a robot explores, and the coarse levels' biases add up as drift);
//   2. judge each tracking result (tracking_evidence.h: failed, unconstrained, not converged, lost overlap,
//      far from the constant-velocity prediction); a doubted result at a coarse level is tracked again,
//      `retrack_levels` finer, before anything is accepted. When the finer pass lands on the coarse pose
//      (within confirm_translation_m / confirm_rotation_deg) the coarse result is confirmed and the level
//      stays; otherwise, or when the frame stays doubtful, the level goes finer for `hold_frames`. An
//      unconstrained view (a blank wall) is re-tracked too, but moves the level only when the finer pass
//      finds it constrained: finer images rarely add structure that a coarse one lacks;
//   3. correct a pose only when ICP failed (even after the re-track): constant-velocity extrapolation for at
//      most `correction_max_extrapolated_frames` frames, then the previous pose is held. Fast motion that ICP
//      tracks is never replaced;
//   4. start the next frame's ICP from the constant-velocity prediction (`predict_start`): at 0.06 m and 4
//      degrees per frame the last pose is 10-20 cm from the truth at the scene's depth, beyond ICP's 0.1 m
//      pairing distance, while the prediction misses only by the change of motion in one frame. The motion
//      is learnt from every tracked frame, weakly constrained ones included: forgetting it there was measured
//      worse (config/README.md, predict_start);
//   5. fuse a frame only when it brings something new (integration_gate.h); a corrected frame or one doubted
//      for anything but its view or a confirmed fast motion is never fused (except a frame ICP left unconverged
//      at the finest level, where no re-track can settle it: fused as DEFAULT fuses it, or the map stops
//      following the camera), and a frame not fused keeps the reference maps.
// Every decision is visible per frame: triggers (retrack, doubt, unconstrained, correction, skip_integrate)
// and a reason whenever the level changes.

#include <array>
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "controller/controller.h"
#include "controller/integration_gate.h"
#include "controller/knob_ladder.h"
#include "controller/tracking_evidence.h"

namespace sb {

struct AdaptiveConfig {
  int bootstrapFrames = 4;         // frames [0, bootstrapFrames) stay at the finest level (the first map)
  int retrackLevels = 1;           // a doubted frame is tracked again this many levels finer (0 = never)
  int holdFrames = 15;             // frames at the finer level after a doubt before relaxing
  int relaxFrames = 3;             // undoubted frames per level towards approximation
  int maxExtrapolatedFrames = 5;   // failed frames in a row extrapolated; later ones hold the previous pose
  // The coarsest level while the robot's odometry drives the frames (a robot exploring: docs/odometry.md): the
  // coarse levels' per-frame biases add up as drift along a drive where no mapped surface anchors the view.
  int maxLevelWithOdometry = 0;
  // While the odometry drives the frames (docs/odometry.md, "adaptive on a robot"): the wheels carry the pose
  // between tracked frames, so only every tracking_rate_with_odometry-th frame is tracked (the others take the
  // last pose moved by the wheels' step: millimetres off over one frame); ICP starts from the wheels' prediction,
  // so icp_iterations_with_odometry (finest, mid, coarsest) converge; the reference maps are raycast at
  // reference_csr_with_odometry (0: the frame's own; the input's resolution carries the accuracy). After a doubt,
  // for hold_frames, every frame is tracked with the ladder's iterations.
  int trackingRateWithOdometry = 3;
  std::array<int, 3> icpIterationsWithOdometry{5, 3, 2};
  int referenceCsrWithOdometry = 2;
  // A re-track that lands within these of the coarse pose confirms it: the level stays. Farther, the coarse
  // level was wrong here and the level goes finer for hold_frames.
  double confirmTranslationM = 0.01;  // m
  double confirmRotationDeg = 1.0;    // degrees
  bool predictStart = true;        // ICP starts from the constant-velocity prediction, not the last pose
  bool integrateUnconstrained = true;  // fuse frames whose view left a motion free (see finish())
  // ICP keeps its start pose along motions whose conditioning is below this (IcpStart): along a motion that
  // a pure plane leaves free its update is noise over a near-zero eigenvalue. Off (0) by default: a weak view
  // with a sliver of structure (conditioning 0.0002-0.0006) still carries the motion, and holding it there
  // lost a handheld sequence; 0.0006 for a camera without odometry among bare walls (config/README.md).
  double icpHoldConditioning = 0.0;
  // The learnt motion follows a tracked frame along each motion by c / (c + learn_conditioning), c the view's
  // structure conditioning along it (blendByStructure): whole where the view fixes the motion, hardly at all
  // along what it leaves free. 0: the whole measured motion.
  double learnConditioning = 0.003;
  EvidenceParams evidence;
  IntegrationParams integration;
  KnobLadder ladder;

  // Section keys: bootstrap_frames, retrack_levels, hold_frames, relax_frames,
  // correction_max_extrapolated_frames, predict_start, integrate_unconstrained, icp_hold_conditioning,
  // learn_conditioning, confirm_translation_m, confirm_rotation_deg, and those of EvidenceParams,
  // IntegrationParams and KnobLadder.
  void read(ConfigReader& reader);
  nlohmann::json toJson() const;  // every key read() reads, with its value
};

class AdaptiveController final : public Controller {
 public:
  AdaptiveController(std::string name, const AdaptiveConfig& config);
  const std::string& name() const override { return name_; }
  Knobs initialKnobs() const override { return config_.ladder.coupled(0); }
  Decision decide(const Observation& observation) override;

  int level() const { return level_; }

 private:
  Decision finish(const Observation& o, const Doubt& doubt, Decision d);
  void setLevel(int level, const std::string& reason, Decision& d);
  // The knobs of `level` for the next frame: the ladder's, with the odometry's tracking rate and iterations
  // while the odometry drives the frames and no doubt is held (`frame`: the frame deciding).
  Knobs nextKnobs(int level, bool odometry, size_t frame) const;
  // Whether `knobs` are those of `level` (compute size and ICP threshold: the rates and iterations may differ).
  bool atLevel(const Knobs& knobs, int level) const;
  // Fills the decision's next knobs, level and reference size.
  void conclude(const Observation& o, Decision& d) const;
  // The re-tracked pose `o.pose` lands within confirm_translation_m / confirm_rotation_deg of the first pass.
  bool passesAgree(const Observation& o) const;

  std::string name_;
  AdaptiveConfig config_;
  TrackingEvidence evidence_;
  MotionModel motion_;
  IntegrationGate gate_;
  int level_ = 0;  // the ladder's level: 0 the finest
  size_t seen_ = 0;          // observations of distinct frames
  size_t holdUntil_ = 0;     // the last frame whose decision may not relax the level
  int undoubted_ = 0;        // undoubted frames since the last level change or doubt
  int failedInARow_ = 0;
  Doubt firstPass_;          // the doubt that asked for the pending re-track
  Eigen::Isometry3d firstPassPose_ = Eigen::Isometry3d::Identity();  // the coarse pose of that frame
};

}  // namespace sb
