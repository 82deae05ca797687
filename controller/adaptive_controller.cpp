#include "controller/adaptive_controller.h"

#include <algorithm>
#include <nlohmann/json.hpp>

namespace sb {

void AdaptiveConfig::read(ConfigReader& r) {
  r.integer("bootstrap_frames", bootstrapFrames, 0, 100000);
  r.integer("retrack_levels", retrackLevels, 0, 16);
  r.integer("hold_frames", holdFrames, 0, 100000);
  r.integer("relax_frames", relaxFrames, 1, 100000);
  r.integer("correction_max_extrapolated_frames", maxExtrapolatedFrames, 0, 1000);
  r.integer("max_level_with_odometry", maxLevelWithOdometry, 0, 16);
  r.integer("tracking_rate_with_odometry", trackingRateWithOdometry, 1, kMaxRate);
  std::vector<int> iterations(icpIterationsWithOdometry.begin(), icpIterationsWithOdometry.end());
  r.integers("icp_iterations_with_odometry", iterations, 0, kMaxIterations, 3, 3);
  if (iterations[0] < 1) r.fail("icp_iterations_with_odometry", "at least 1 iteration at the finest level");
  std::copy(iterations.begin(), iterations.end(), icpIterationsWithOdometry.begin());
  r.integer("reference_csr_with_odometry", referenceCsrWithOdometry, 0, 8);
  if (referenceCsrWithOdometry != 0 && !validCsr(referenceCsrWithOdometry))
    r.fail("reference_csr_with_odometry", "0 (the frame's own compute size), 1, 2, 4 or 8");
  r.boolean("predict_start", predictStart);
  r.boolean("integrate_unconstrained", integrateUnconstrained);
  r.number("icp_hold_conditioning", icpHoldConditioning, 0.0, 1.0);
  r.number("learn_conditioning", learnConditioning, 0.0, 1.0);
  r.number("confirm_translation_m", confirmTranslationM, 0.0, 10.0);
  r.number("confirm_rotation_deg", confirmRotationDeg, 0.0, 180.0);
  evidence.read(r);
  integration.read(r);
  ladder.read(r);
}

nlohmann::json AdaptiveConfig::toJson() const {
  nlohmann::json j = {{"bootstrap_frames", bootstrapFrames},
                      {"retrack_levels", retrackLevels},
                      {"hold_frames", holdFrames},
                      {"relax_frames", relaxFrames},
                      {"correction_max_extrapolated_frames", maxExtrapolatedFrames},
                      {"max_level_with_odometry", maxLevelWithOdometry},
                      {"tracking_rate_with_odometry", trackingRateWithOdometry},
                      {"icp_iterations_with_odometry", icpIterationsWithOdometry},
                      {"reference_csr_with_odometry", referenceCsrWithOdometry},
                      {"predict_start", predictStart},
                      {"integrate_unconstrained", integrateUnconstrained},
                      {"icp_hold_conditioning", icpHoldConditioning},
                      {"learn_conditioning", learnConditioning},
                      {"confirm_translation_m", confirmTranslationM},
                      {"confirm_rotation_deg", confirmRotationDeg}};
  evidence.toJson(j);
  integration.toJson(j);
  ladder.toJson(j);
  return j;
}

AdaptiveController::AdaptiveController(std::string name, const AdaptiveConfig& config)
    : name_(std::move(name)),
      config_(config),
      evidence_(config.evidence),
      gate_(config.integration) {}

void AdaptiveController::setLevel(int level, const std::string& reason, Decision& d) {
  level = std::clamp(level, 0, config_.ladder.maxLevel);
  if (level == level_) return;
  const Knobs from = config_.ladder.coupled(level_), to = config_.ladder.coupled(level);
  d.reason = reason + ": csr " + std::to_string(from.csr) + " -> " + std::to_string(to.csr);
  level_ = level;
  undoubted_ = 0;
}

Knobs AdaptiveController::nextKnobs(int level, bool odometry, size_t frame) const {
  Knobs k = config_.ladder.coupled(level);
  if (odometry && frame >= holdUntil_) {
    k.trackingRate = config_.trackingRateWithOdometry;
    k.pyramidIterations = config_.icpIterationsWithOdometry;
  }
  return k;
}

bool AdaptiveController::atLevel(const Knobs& knobs, int level) const {
  const Knobs k = config_.ladder.coupled(level);
  return knobs.csr == k.csr && knobs.icpThreshold == k.icpThreshold;
}

void AdaptiveController::conclude(const Observation& o, Decision& d) const {
  d.level = level_;
  d.next = nextKnobs(level_, o.odometry, o.frame);
  if (o.odometry && config_.referenceCsrWithOdometry > 0) d.referenceCsr = config_.referenceCsrWithOdometry;
}

Decision AdaptiveController::decide(const Observation& o) {
  Decision d;
  d.nextHoldBelowConditioning = config_.icpHoldConditioning;
  if (!o.retracked) ++seen_;
  if (!o.trackingAttempted) {  // the pipeline's bootstrap (always fused) or a frame skipped by tr
    gate_.skipped();  // the max gap counts frames, tracked or not
    d.triggers |= kTriggerBootstrap;
    conclude(o, d);
    return d;
  }
  const Eigen::Isometry3d predicted = motion_.predict(o.previousPose);
  const Doubt doubt = evidence_.judge(o, predicted, motion_.known());
  // A doubted coarse result is tracked again finer before anything is accepted.
  const int finer = std::max(0, level_ - config_.retrackLevels);
  if (doubt.doubtful() && !o.retracked && config_.retrackLevels > 0 && finer < level_ && atLevel(o.knobs, level_)) {
    firstPass_ = doubt;
    firstPassPose_ = o.pose;
    d.retrack = config_.ladder.coupled(finer);
    d.triggers |= kTriggerDoubt;
    conclude(o, d);
    d.reason = "retrack: " + doubt.why;
    return d;
  }
  return finish(o, doubt, d);
}

bool AdaptiveController::passesAgree(const Observation& o) const {
  return translationBetween(firstPassPose_, o.pose) <= config_.confirmTranslationM &&
         rotationBetweenDeg(firstPassPose_, o.pose) <= config_.confirmRotationDeg;
}

Decision AdaptiveController::finish(const Observation& o, const Doubt& doubt, Decision d) {
  // Pose: corrected only when ICP failed, or when a re-track measured nothing: doubted on its own evidence,
  // away from the first pass and off the prediction by more than a camera changes its motion in one frame (the
  // 5 m-volume drive: an unconverged csr 8 pass, then a csr 4 pass 0.13 m off with half the inliers).
  const bool unconfirmed = o.tracked && o.retracked && motion_.known() && doubt.doubtful() &&
                           doubt.kind != Doubt::prediction && !passesAgree(o) &&
                           evidence_.offPrediction(o, motion_.predict(o.previousPose));
  bool corrected = false;
  if (!o.tracked || unconfirmed) {
    ++failedInARow_;
    if (failedInARow_ <= config_.maxExtrapolatedFrames && motion_.known()) {
      d.correctedPose = motion_.predict(o.previousPose);
      d.triggers |= kTriggerCorrection;
      corrected = true;
    } else {
      motion_.forget();  // lost for too long: the pipeline holds the previous pose
    }
  } else {
    failedInARow_ = 0;
    // A motion that ICP had not converged on (still moving after every iteration) or that is off the prediction by
    // more than a camera can change its motion in one frame, with no second pass to confirm it, is not learnt: the
    // next frame starts from this pose, as DEFAULT does. Learnt, ICP's slide along a motion the view barely
    // constrains becomes the next start pose, the next slide adds to it, and the prior feeds on itself (a sparse
    // corridor seen lengthwise: 0.05 -> 0.50 m/frame in 5 frames while the robot stood; with the prediction
    // doubt alone left out it still ran away from frame 13).
    // A re-track is no confirmation by itself: a second pass that is doubted too and lands away from the first
    // one confirms nothing (the 5 m-volume drive: csr 8 unconverged, the csr 4 re-track 0.13 m off the
    // prediction with half the inliers; learnt, it lost the next frames).
    const bool unsettled = o.retracked ? doubt.doubtful() && !passesAgree(o)
                                       : doubt.kind == Doubt::prediction || doubt.kind == Doubt::notConverged;
    if (unsettled) {
      motion_.forget();
    } else {
      motion_.learn(o.previousPose, o.pose, o.quality, config_.learnConditioning);
    }
    evidence_.accept(o);
  }
  if (o.quality.known && !o.quality.constrained) d.triggers |= kTriggerUnconstrained;

  // Level: finer on doubt, unless a re-track confirmed the coarse pose; else relax. An unconstrained view is
  // a property of the scene, not of the level: it moves the level only when the finer re-track found the
  // structure that the coarse images lost (the finer pass is constrained).
  const auto counts = [&](const Doubt& x, bool second) {
    if (x.kind == Doubt::unconstrained) return false;
    // Both levels disagreeing with the prediction but agreeing with each other: the motion is real.
    return x.doubtful() && !(second && x.kind == Doubt::prediction);
  };
  const bool secondDoubted = counts(doubt, o.retracked);
  // A robot driving (its odometry present) explores: no coarser than max_level_with_odometry.
  const int ceiling =
      o.odometry ? std::min(config_.maxLevelWithOdometry, config_.ladder.maxLevel) : config_.ladder.maxLevel;
  bool confirmed = false, doubted = false;
  if (!o.retracked) {
    doubted = counts(doubt, false);
  } else if (firstPass_.kind == Doubt::unconstrained) {
    doubted = secondDoubted || evidence_.wellConstrained(o);
    confirmed = !doubted;
  } else {
    confirmed = !secondDoubted && firstPass_.kind != Doubt::failed && passesAgree(o);
    doubted = !confirmed;
  }
  if (seen_ <= static_cast<size_t>(config_.bootstrapFrames)) {
    d.triggers |= kTriggerBootstrap;
  } else if (doubted) {
    const int target = std::max(0, level_ - std::max(1, config_.retrackLevels));
    setLevel(target, "doubt (" + (o.retracked ? firstPass_.why : doubt.why) + ")", d);
    holdUntil_ = o.frame + static_cast<size_t>(config_.holdFrames);
    undoubted_ = 0;
  } else if (confirmed) {
    d.reason = "coarse pose confirmed (" + firstPass_.why + ")";
  } else if (level_ > ceiling) {
    setLevel(ceiling, "the robot's odometry (max_level_with_odometry)", d);
  } else if (++undoubted_ >= config_.relaxFrames && o.frame > holdUntil_ && level_ < ceiling) {
    setLevel(level_ + 1, "relax (" + std::to_string(config_.relaxFrames) + " frames without doubt)", d);
  }

  // Integration: only frames that bring something new and whose pose is trusted. A frame ICP left unconverged at
  // the finest level is trusted as DEFAULT trusts it: no finer pass can settle it, and left unfused the map stops
  // following the camera (a sparse corridor seen lengthwise: lost from frame 204 of 300, all tracked by DEFAULT).
  // An unconstrained frame is fused too: its pose can be off only along motions that leave the visible
  // geometry unchanged (sliding along the wall in view), so fusing it does not bend the model.
  const bool finest = atLevel(o.knobs, 0);
  const bool trusted = o.tracked && !corrected &&
                       (doubt.kind == Doubt::none || doubt.kind == Doubt::prediction ||
                        (doubt.kind == Doubt::notConverged && finest) ||
                        (doubt.kind == Doubt::unconstrained && config_.integrateUnconstrained));
  const Eigen::Isometry3d finalPose = d.correctedPose ? *d.correctedPose : o.pose;
  d.integrate = gate_.decide(finalPose, trusted, o.odometry);
  if (!*d.integrate) {
    d.triggers |= kTriggerSkipIntegrate;
    d.keepReference = true;
  }
  if (config_.predictStart && motion_.known())
    d.nextStartPose = motion_.predict(finalPose);
  conclude(o, d);
  return d;
}

}  // namespace sb
