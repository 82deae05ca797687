#include "controller/step_controller.h"

#include <algorithm>
#include <nlohmann/json.hpp>

namespace sb {

void StepConfig::read(ConfigReader& r) {
  r.integer("bootstrap_frames", bootstrapFrames, 1, 100000);
  r.integer("approximation_hold_frames", approximationHoldFrames, 1, 1000);
  r.integer("precision_below_level", precisionBelowLevel, 0, 16);
  r.integer("approximation_above_level", approximationAboveLevel, 0, 16);
  r.boolean("surface_detection", surfaceDetection);
  r.boolean("pose_correction", poseCorrection);
  r.integer("csr_max_level", csrMaxLevel, 0, 15);
  r.integer("icp_max_level", icpMaxLevel, 0, 15);
  r.integer("pd0_max_level", pd0MaxLevel, 0, 15);
  r.integer("icp_base_level", icpBaseLevel, 0, 15);
  pid.read(r);
  surface.read(r);
  correction.read(r);
  ladder.read(r);
}

nlohmann::json StepConfig::toJson() const {
  nlohmann::json j = {{"bootstrap_frames", bootstrapFrames},
                      {"approximation_hold_frames", approximationHoldFrames},
                      {"precision_below_level", precisionBelowLevel},
                      {"approximation_above_level", approximationAboveLevel},
                      {"surface_detection", surfaceDetection},
                      {"pose_correction", poseCorrection},
                      {"csr_max_level", csrMaxLevel},
                      {"icp_max_level", icpMaxLevel},
                      {"pd0_max_level", pd0MaxLevel},
                      {"icp_base_level", icpBaseLevel}};
  pid.toJson(j);
  surface.toJson(j);
  correction.toJson(j);
  ladder.toJson(j);
  return j;
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
