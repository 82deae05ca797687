#include "power/energy_counter.h"

namespace sb::power {

uint64_t counterDelta(uint64_t previous, uint64_t current, uint64_t maxRange) {
  if (current >= previous) return current - previous;
  if (maxRange == 0 || previous > maxRange) return current;  // no known range: count from the wrap
  return (maxRange - previous) + current;
}

std::optional<PowerSample> EnergyCounter::update(int64_t tNs, uint64_t units, uint64_t maxRange) {
  if (!started_ || tNs <= lastNs_) {
    if (!started_) {
      started_ = true;
      lastNs_ = tNs;
      lastUnits_ = units;
    }
    return std::nullopt;
  }
  const uint64_t delta = counterDelta(lastUnits_, units, maxRange);
  PowerSample s;
  s.tNs = tNs;
  s.watts = static_cast<double>(delta) * joulesPerUnit_ / nsToSeconds(tNs - lastNs_);
  lastNs_ = tNs;
  lastUnits_ = units;
  return s;
}

}  // namespace sb::power
