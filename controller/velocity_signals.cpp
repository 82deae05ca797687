#include "controller/velocity_signals.h"

#include <algorithm>
#include <cmath>

#include "controller/controller.h"
#include "core/error.h"

namespace sb {

void PidParams::read(ConfigReader& r) {
  r.number("v_stand_m_per_frame", vStand, 0.0, 1.0);
  r.number("v_low_m_per_frame", vLow, 0.0, 1.0);
  r.number("kp_levels_per_m_per_frame", kp, 0.0, 1e6);
  r.boolean("integral", integral);
  r.integer("integral_window_frames", integralWindowFrames, 1, 1000);
  r.number("integral_threshold_m_per_frame", integralThreshold, 0.0, 1.0);
  r.boolean("derivative", derivative);
  r.integer("derivative_window_frames", derivativeWindowFrames, 2, 1000);
  r.boolean("derivative_allows_approximation", derivativeAllowsApproximation);
  if (!(vStand > vLow))
    throw Error(r.at("v_stand_m_per_frame") + " must be larger than 'v_low_m_per_frame' (" + std::to_string(vStand) +
                " <= " + std::to_string(vLow) + ")");
}

void PidParams::toJson(nlohmann::json& j) const {
  j["v_stand_m_per_frame"] = vStand;
  j["v_low_m_per_frame"] = vLow;
  j["kp_levels_per_m_per_frame"] = kp;
  j["integral"] = integral;
  j["integral_window_frames"] = integralWindowFrames;
  j["integral_threshold_m_per_frame"] = integralThreshold;
  j["derivative"] = derivative;
  j["derivative_window_frames"] = derivativeWindowFrames;
  j["derivative_allows_approximation"] = derivativeAllowsApproximation;
}

void VelocityHistory::push(double velocity) {
  v_.push_back(velocity);
  while (v_.size() > capacity_) v_.pop_front();
}

double VelocityHistory::mean(size_t frames) const {
  const size_t n = std::min(frames, v_.size());
  if (n == 0) return 0.0;
  double sum = 0;
  for (size_t i = v_.size() - n; i < v_.size(); ++i) sum += v_[i];
  return sum / double(n);
}

bool VelocityHistory::nonDecreasing(size_t frames) const {
  if (frames < 2 || v_.size() < frames) return false;
  for (size_t i = v_.size() - frames + 1; i < v_.size(); ++i)
    if (v_[i] < v_[i - 1]) return false;
  return true;
}

bool VelocityHistory::strictlyDecreasing(size_t frames) const {
  if (frames < 2 || v_.size() < frames) return false;
  for (size_t i = v_.size() - frames + 1; i < v_.size(); ++i)
    if (!(v_[i] < v_[i - 1])) return false;
  return true;
}

PidResult pidTarget(const VelocityHistory& history, const PidParams& p, int maxLevel) {
  PidResult r;
  const double kp = p.kp > 0 ? p.kp : double(maxLevel) / (p.vStand - p.vLow);
  const double raw = std::trunc(kp * (p.vStand - history.newest()));
  r.proportional = static_cast<int>(std::clamp(raw, 0.0, double(maxLevel)));
  int target = r.proportional;
  if (p.integral && history.mean(static_cast<size_t>(p.integralWindowFrames)) > p.integralThreshold) {
    --target;
    r.triggers |= kTriggerIntegral;
  }
  if (p.derivative) {
    const size_t window = static_cast<size_t>(p.derivativeWindowFrames);
    if (history.nonDecreasing(window)) {
      --target;
      r.triggers |= kTriggerDerivativeUp;
    } else if (p.derivativeAllowsApproximation && history.strictlyDecreasing(window)) {
      ++target;
      r.triggers |= kTriggerDerivativeDown;
    }
  }
  r.target = std::clamp(target, 0, maxLevel);
  return r;
}

}  // namespace sb
