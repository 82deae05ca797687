#include "controller/budget_controller.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "core/error.h"

namespace sb {

void BudgetConfig::read(ConfigReader& r) {
  r.number("target_frame_ms", targetFrameMs, 0.0, 1e6);
  r.number("target_joules_per_frame", targetJoules, 0.0, 1e6);
  r.number("ema_alpha", emaAlpha, 0.01, 1.0);
  r.number("margin", margin, 0.0, 0.9);
  r.integer("reprobe_frames", reprobeFrames, 1, 1000000);
  r.integer("bootstrap_frames", bootstrapFrames, 1, 100000);
  r.boolean("surface_detection", surfaceDetection);
  r.boolean("pose_correction", poseCorrection);
  rate.read(r);
  surface.read(r);
  correction.read(r);
  ladder.read(r);
  r.finish();
  if ((targetFrameMs > 0) == (targetJoules > 0))
    throw Error(r.where() + ": set exactly one of 'target_frame_ms' and 'target_joules_per_frame' (> 0), e.g. "
                "{\"target_frame_ms\": 33}");
}

nlohmann::json BudgetConfig::toJson() const {
  nlohmann::json j = {{"target_frame_ms", targetFrameMs},
                      {"target_joules_per_frame", targetJoules},
                      {"ema_alpha", emaAlpha},
                      {"margin", margin},
                      {"reprobe_frames", reprobeFrames},
                      {"bootstrap_frames", bootstrapFrames},
                      {"surface_detection", surfaceDetection},
                      {"pose_correction", poseCorrection}};
  rate.toJson(j);
  surface.toJson(j);
  correction.toJson(j);
  ladder.toJson(j);
  return j;
}

BudgetController::BudgetController(std::string name, const BudgetConfig& config)
    : name_(std::move(name)),
      config_(config),
      corrector_(config.correction),
      limiter_(config.rate),
      estimate_(static_cast<size_t>(config.ladder.maxLevel + 1), -1.0),
      measuredAt_(static_cast<size_t>(config.ladder.maxLevel + 1), 0) {}

Decision BudgetController::decide(const Observation& o) {
  Decision d;
  // The cost of the previous frame, attributed to the level it ran at.
  const bool energy = config_.targetJoules > 0;
  const double target = energy ? config_.targetJoules : config_.targetFrameMs;
  const std::optional<double> cost =
      energy ? o.latestJoules : (o.previousComputationMs > 0 ? std::optional<double>(o.previousComputationMs) : std::nullopt);
  if (cost && seen_ > 0) {
    double& e = estimate_[static_cast<size_t>(previousLevel_)];
    e = e < 0 ? *cost : config_.emaAlpha * *cost + (1 - config_.emaAlpha) * e;
    measuredAt_[static_cast<size_t>(previousLevel_)] = seen_;
  }
  for (size_t l = 0; l < estimate_.size(); ++l)
    if (estimate_[l] >= 0 && seen_ - measuredAt_[l] > static_cast<size_t>(config_.reprobeFrames)) estimate_[l] = -1.0;

  if (config_.poseCorrection && (d.correctedPose = corrector_.correct(o))) d.triggers |= kTriggerCorrection;
  const bool smooth =
      config_.surfaceDetection && o.depth && detectSmoothSurface(*o.depth, o.depthScale, config_.surface).smooth;
  if (smooth) d.triggers |= kTriggerSurface;
  ++seen_;

  const int maxLevel = config_.ladder.maxLevel;
  if (seen_ < static_cast<size_t>(config_.bootstrapFrames)) {
    limiter_.reset(0);
    d.triggers |= kTriggerBootstrap;
  } else {
    // The lowest level that fits: known estimates must fit the target; an unknown level fits when the next
    // more approximate level is known to fit with the margin to spare.
    int wanted = maxLevel;
    for (int l = 0; l <= maxLevel; ++l) {
      const double e = estimate_[static_cast<size_t>(l)];
      const double next = l < maxLevel ? estimate_[static_cast<size_t>(l + 1)] : -1.0;
      const bool fits = e >= 0 ? e <= target : (next >= 0 && next <= (1 - config_.margin) * target);
      if (fits) {
        wanted = l;
        break;
      }
    }
    const double current = estimate_[static_cast<size_t>(limiter_.level())];
    if (current > target) d.triggers |= kTriggerBudget;
    if (smooth) --wanted;
    if (d.correctedPose) --wanted;
    if (limiter_.update(std::clamp(wanted, 0, maxLevel))) d.triggers |= kTriggerHold;
  }
  d.level = limiter_.level();
  previousLevel_ = d.level;
  d.next = config_.ladder.coupled(d.level);
  return d;
}

}  // namespace sb
