#pragma once
// The values that flow between meters, the energy ledger and its users. Times are CLOCK_MONOTONIC in integer
// nanoseconds (exact differences; a double of seconds since boot would lose precision on long uptimes).

#include <cmath>
#include <cstdint>
#include <string>

namespace sb::power {

// How a meter's watts relate to time, and therefore how the ledger integrates them.
enum class SampleKind {
  instantaneous,    // power at the sample's time: linear interpolation between samples (serial meters, INA231)
  intervalAverage,  // mean power over (previous sample, this sample]: piecewise constant (energy counters:
                    // RAPL, NVML); integrating these gives the counter's energy exactly
};

const char* sampleKindName(SampleKind kind);  // "instantaneous" / "interval_average"
// Throws sb::Error naming `where` for an unknown name.
SampleKind parseSampleKind(const std::string& name, const std::string& where);

struct PowerSample {
  int64_t tNs = 0;          // CLOCK_MONOTONIC when the value was read from the device
  double watts = 0.0;       // W
  double volts = NAN;       // V, NaN when the meter does not report it
  double amps = NAN;        // A, NaN when the meter does not report it
  bool gapBefore = false;   // the meter was not measuring between the previous sample and this one
};

// One frame's processing interval, as the SLAM loop measured it (CLOCK_MONOTONIC ns).
struct FrameInterval {
  uint64_t frame = 0;
  int64_t startNs = 0;
  int64_t endNs = 0;
};

// The energy of one frame. `known` is false when any part of [start, end] lies in a meter gap, before the
// first sample, or after the last sample at shutdown: such frames carry no number (never guessed).
struct FrameEnergy {
  uint64_t frame = 0;
  int64_t startNs = 0;
  int64_t endNs = 0;
  bool known = false;
  double joules = NAN;            // J over [start, end]
  double joulesAboveIdle = NAN;   // J minus idle baseline power x duration (equals joules without a baseline)
  double meanWatts = NAN;         // joules / duration
  std::string unknownReason;      // empty when known
};

inline double nsToSeconds(int64_t ns) { return static_cast<double>(ns) * 1e-9; }
inline int64_t secondsToNs(double s) { return static_cast<int64_t>(std::llround(s * 1e9)); }

}  // namespace sb::power
