#pragma once
// Turning a cumulative energy counter (RAPL energy_uj, NVML total energy) into interval-average power samples:
// each read after the first yields (energy since the previous read) / (time since the previous read), stamped
// at the read. Integrated piecewise constant, these samples reproduce the counter's energy exactly.

#include <cstdint>
#include <optional>

#include "power/sample.h"

namespace sb::power {

// Energy between two reads of a counter that wraps to 0 after `maxRange` (RAPL max_energy_range_uj).
// A counter that went backwards is taken to have wrapped once. maxRange 0 = the counter never wraps.
uint64_t counterDelta(uint64_t previous, uint64_t current, uint64_t maxRange);

class EnergyCounter {
 public:
  // `joulesPerUnit`: 1e-6 for microjoules, 1e-3 for millijoules.
  explicit EnergyCounter(double joulesPerUnit) : joulesPerUnit_(joulesPerUnit) {}

  // The first call only records the reading; later calls return the sample for the interval since the last.
  std::optional<PowerSample> update(int64_t tNs, uint64_t units, uint64_t maxRange = 0);

 private:
  double joulesPerUnit_;
  bool started_ = false;
  int64_t lastNs_ = 0;
  uint64_t lastUnits_ = 0;
};

}  // namespace sb::power
