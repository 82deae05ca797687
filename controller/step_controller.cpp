#include "controller/step_controller.h"

#include <algorithm>
#include <nlohmann/json.hpp>

namespace sb {

StepConfig parseStepConfig(const nlohmann::json& section, const std::string& where) {
  ConfigReader r(section, where);
  StepConfig c;
  r.integer("bootstrap_frames", c.bootstrapFrames, 1, 100000);
  r.integer("approximation_hold_frames", c.approximationHoldFrames, 1, 1000);
  r.integer("precision_below_level", c.precisionBelowLevel, 0, 16);
  r.integer("approximation_above_level", c.approximationAboveLevel, 0, 16);
  r.boolean("surface_detection", c.surfaceDetection);
  r.boolean("pose_correction", c.poseCorrection);
  r.integer("csr_max_level", c.csrMaxLevel, 0, 15);
  r.integer("icp_max_level", c.icpMaxLevel, 0, 15);
  r.integer("pd0_max_level", c.pd0MaxLevel, 0, 15);
  r.integer("icp_base_level", c.icpBaseLevel, 0, 15);
  c.pid.read(r);
  c.surface.read(r);
  c.correction.read(r);
  c.ladder.read(r);
  r.finish();
  return c;
}

StepController::StepController(std::string name, const StepConfig& config)
    : name_(std::move(name)),
      config_(config),
      history_(static_cast<size_t>(std::max(config.pid.integralWindowFrames, config.pid.derivativeWindowFrames))),
      corrector_(config.correction) {
  const int csrMax = std::min(config.csrMaxLevel, static_cast<int>(config.ladder.csrLevels.size()) - 1);
  const int icpMax = std::min(config.icpMaxLevel, static_cast<int>(config.ladder.icpLevels.size()) - 1);
  const int pd0Max = std::min(config.pd0MaxLevel, static_cast<int>(config.ladder.pd0Levels.size()) - 1);
  moves_.insert(moves_.end(), static_cast<size_t>(std::max(csrMax, 0)), 0);
  moves_.insert(moves_.end(), static_cast<size_t>(std::max(icpMax - config.icpBaseLevel, 0)), 1);
  moves_.insert(moves_.end(), static_cast<size_t>(std::max(pd0Max, 0)), 2);
}

Knobs StepController::knobsAt(int position) const {
  int levels[3] = {0, config_.icpBaseLevel, 0};
  for (int i = 0; i < std::min(position, static_cast<int>(moves_.size())); ++i) ++levels[moves_[static_cast<size_t>(i)]];
  return config_.ladder.at(levels[0], levels[1], levels[2]);
}

Decision StepController::decide(const Observation& o) {
  Decision d;
  Eigen::Isometry3d finalPose = o.pose;
  if (config_.poseCorrection && (d.correctedPose = corrector_.correct(o))) {
    finalPose = *d.correctedPose;
    d.triggers |= kTriggerCorrection;
  }
  history_.push((finalPose.translation() - o.previousPose.translation()).norm());
  const bool smooth =
      config_.surfaceDetection && o.depth && detectSmoothSurface(*o.depth, o.depthScale, config_.surface).smooth;
  if (smooth) d.triggers |= kTriggerSurface;
  ++seen_;
  if (seen_ < static_cast<size_t>(config_.bootstrapFrames)) {
    position_ = 0;
    held_ = 0;
    d.triggers |= kTriggerBootstrap;
  } else {
    const PidResult pid = pidTarget(history_, config_.pid, config_.ladder.maxLevel);
    d.triggers |= pid.triggers;
    const int target = pid.target - (smooth ? 1 : 0) - (d.correctedPose ? 1 : 0);
    if (target < config_.precisionBelowLevel) {
      position_ = std::max(0, position_ - 1);
      held_ = 0;
    } else if (target > config_.approximationAboveLevel && position_ + 1 < positions()) {
      if (++held_ >= config_.approximationHoldFrames) {
        ++position_;
        held_ = 0;
      } else {
        d.triggers |= kTriggerHold;
      }
    } else {
      held_ = 0;
    }
  }
  d.level = position_;
  d.next = knobsAt(position_);
  return d;
}

}  // namespace sb
