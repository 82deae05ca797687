#pragma once
// Asymmetric rate limits on the approximation level (architecture.md D4): towards precision at once, at most
// `precision_step_levels` per frame; towards approximation only after the target has stayed above the
// current level for `approximation_hold_frames` consecutive frames, then `approximation_step_levels`.

#include "core/config_reader.h"

namespace sb {

struct RateLimitParams {
  int precisionStepLevels = 1;
  int approximationHoldFrames = 3;
  int approximationStepLevels = 1;

  // Keys: precision_step_levels, approximation_hold_frames, approximation_step_levels.
  void read(ConfigReader& reader);
  void toJson(nlohmann::json& section) const;  // adds the same keys with their values
};

class RateLimiter {
 public:
  explicit RateLimiter(const RateLimitParams& params) : params_(params) {}
  // Moves the level towards `target`; returns true when a move towards approximation is being held back.
  bool update(int target);
  int level() const { return level_; }
  void reset(int level = 0) {
    level_ = level;
    held_ = 0;
  }

 private:
  RateLimitParams params_;
  int level_ = 0;
  int held_ = 0;  // consecutive frames with target > level
};

}  // namespace sb
