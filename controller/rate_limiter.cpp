#include "controller/rate_limiter.h"

#include <algorithm>

namespace sb {

void RateLimitParams::read(ConfigReader& r) {
  r.integer("precision_step_levels", precisionStepLevels, 1, 16);
  r.integer("approximation_hold_frames", approximationHoldFrames, 1, 1000);
  r.integer("approximation_step_levels", approximationStepLevels, 1, 16);
}

void RateLimitParams::toJson(nlohmann::json& j) const {
  j["precision_step_levels"] = precisionStepLevels;
  j["approximation_hold_frames"] = approximationHoldFrames;
  j["approximation_step_levels"] = approximationStepLevels;
}

bool RateLimiter::update(int target) {
  if (target < level_) {
    level_ = std::max(target, level_ - params_.precisionStepLevels);
    held_ = 0;
    return false;
  }
  if (target == level_) {
    held_ = 0;
    return false;
  }
  if (++held_ < params_.approximationHoldFrames) return true;
  level_ = std::min(target, level_ + params_.approximationStepLevels);
  held_ = 0;
  return false;
}

}  // namespace sb
