#pragma once
// Re-accounting a finished run: a recorded power trace (power_trace.h) plus the run's per-frame log gives the
// same per-frame joules as the live sampler did (or new ones, e.g. with another idle baseline).
//
// The per-frame log is JSON lines (frames.jsonl); each line needs
//   "frame":            the frame index (integer)
//   "t_start_mono_ns":  CLOCK_MONOTONIC (ns, integer) when the SLAM thread began processing the frame
//   "t_end_mono_ns":    CLOCK_MONOTONIC (ns, integer) when processing the frame finished
// (other keys are ignored). Both times must come from the machine and boot that recorded the trace.

#include <string>
#include <vector>

#include "power/energy_ledger.h"
#include "power/power_trace.h"
#include "power/sample.h"

namespace sb::power {

constexpr const char* kFrameIndexKey = "frame";
constexpr const char* kFrameStartKey = "t_start_mono_ns";
constexpr const char* kFrameEndKey = "t_end_mono_ns";

// Throws sb::Error naming the file, line and missing key.
std::vector<FrameInterval> readFrameIntervals(const std::string& framesJsonlPath);

struct OfflineOptions {
  double idleWatts = 0.0;
  int64_t maxSampleGapNs = 0;  // 0 = automatic from the trace's nominal period (as the live sampler does)
};

struct OfflineResult {
  std::vector<FrameEnergy> frames;  // in the order of the log
  EnergyTotals totals;
};

OfflineResult accountOffline(const PowerTrace& trace, const std::vector<FrameInterval>& frames,
                             const OfflineOptions& options = {});

}  // namespace sb::power
