#include "controller/slambooster_controller.h"

#include <algorithm>
#include <nlohmann/json.hpp>

namespace sb {

void SlamBoosterConfig::read(ConfigReader& r) {
  r.integer("bootstrap_frames", bootstrapFrames, 1, 100000);
  r.boolean("surface_detection", surfaceDetection);
  r.boolean("pose_correction", poseCorrection);
  r.boolean("half_precision", halfPrecision);
  pid.read(r);
  rate.read(r);
  surface.read(r);
  correction.read(r);
  ladder.read(r);
}

nlohmann::json SlamBoosterConfig::toJson() const {
  nlohmann::json j = {{"bootstrap_frames", bootstrapFrames},
                      {"surface_detection", surfaceDetection},
                      {"pose_correction", poseCorrection},
                      {"half_precision", halfPrecision}};
  pid.toJson(j);
  rate.toJson(j);
  surface.toJson(j);
  correction.toJson(j);
  ladder.toJson(j);
  return j;
}

SlamBoosterController::SlamBoosterController(std::string name, const SlamBoosterConfig& config)
    : name_(std::move(name)),
      config_(config),
      history_(static_cast<size_t>(std::max(config.pid.integralWindowFrames, config.pid.derivativeWindowFrames))),
      corrector_(config.correction),
      limiter_(config.rate) {}

Decision SlamBoosterController::decide(const Observation& o) {
  Decision d;
  Eigen::Isometry3d finalPose = o.pose;
  if (config_.poseCorrection) {
    d.correctedPose = corrector_.correct(o);
    if (d.correctedPose) {
      finalPose = *d.correctedPose;
      d.triggers |= kTriggerCorrection;
    }
  }
  history_.push((finalPose.translation() - o.previousPose.translation()).norm());
  const bool smooth = config_.surfaceDetection && o.depth &&
                      detectSmoothSurface(*o.depth, o.depthScale, config_.surface).smooth;
  if (smooth) d.triggers |= kTriggerSurface;
  ++seen_;

  const int maxLevel = config_.ladder.maxLevel;
  if (seen_ < static_cast<size_t>(config_.bootstrapFrames)) {
    // The next frame is still inside the bootstrap.
    limiter_.reset(0);
    d.triggers |= kTriggerBootstrap;
  } else {
    const PidResult pid = pidTarget(history_, config_.pid, maxLevel);
    d.triggers |= pid.triggers;
    int target = pid.target;
    if (smooth) --target;
    if (d.correctedPose) --target;
    if (limiter_.update(std::clamp(target, 0, maxLevel))) d.triggers |= kTriggerHold;
    d.halfPrecision = config_.halfPrecision;
  }
  d.level = limiter_.level();
  d.next = config_.ladder.coupled(d.level);
  return d;
}

}  // namespace sb
