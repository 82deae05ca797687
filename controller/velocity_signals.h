#pragma once
// The velocity tests of SLAMBooster (architecture.md D4), shared by the slambooster, step and budget
// controllers. Velocity v_t (m/frame) is the ITE proxy: faster motion needs more precision.
//   P: target level = clamp(trunc(Kp * (v_stand - v_t)), 0, maxLevel), Kp = maxLevel / (v_stand - v_low)
//   I: mean velocity over the last `integral_window_frames` above `integral_threshold` -> one level more precise
//   D: velocity non-decreasing over the last `derivative_window_frames` -> one level more precise;
//      strictly decreasing over them -> one level less precise (when `derivative_allows_approximation`)

#include <cstdint>
#include <deque>

#include "core/config_reader.h"

namespace sb {

struct PidParams {
  double vStand = 0.030;            // m/frame: at and above this speed, level 0 (no approximation)
  double vLow = 0.004;              // m/frame: at and below this speed, the highest level
  double kp = 0.0;                  // levels per (m/frame); 0 = derived: maxLevel / (vStand - vLow)
  bool integral = true;             // I term on
  int integralWindowFrames = 10;    // frames in the I window
  double integralThreshold = 0.015; // m/frame
  bool derivative = true;           // D term on
  int derivativeWindowFrames = 5;   // frames compared by the D test
  bool derivativeAllowsApproximation = true;  // the paper's text (the original code only raised precision)

  // Keys: v_stand_m_per_frame, v_low_m_per_frame, kp_levels_per_m_per_frame, integral, integral_window_frames,
  // integral_threshold_m_per_frame, derivative, derivative_window_frames, derivative_allows_approximation.
  void read(ConfigReader& reader);
  void toJson(nlohmann::json& section) const;  // adds the same keys with their values
};

// The last velocities of a run, newest last (bounded to the longest window needed).
class VelocityHistory {
 public:
  explicit VelocityHistory(size_t capacity = 64) : capacity_(capacity) {}
  void push(double velocity);
  size_t size() const { return v_.size(); }
  double newest() const { return v_.empty() ? 0.0 : v_.back(); }
  // Mean of the newest `frames` velocities (fewer when the history is shorter; 0 when empty).
  double mean(size_t frames) const;
  // True when the newest `frames` velocities exist and are non-decreasing / strictly decreasing in time.
  bool nonDecreasing(size_t frames) const;
  bool strictlyDecreasing(size_t frames) const;

 private:
  size_t capacity_;
  std::deque<double> v_;
};

struct PidResult {
  int target = 0;          // clamped to [0, maxLevel]
  int proportional = 0;    // the P level alone
  uint32_t triggers = 0;   // kTriggerIntegral / kTriggerDerivativeUp / kTriggerDerivativeDown
};

// The P, I and D tests on `history` (newest = v_t), before the surface and correction triggers.
PidResult pidTarget(const VelocityHistory& history, const PidParams& params, int maxLevel);

}  // namespace sb
