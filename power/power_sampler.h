#pragma once
// A thread that polls one meter and feeds the energy ledger: the daemon's power-sampling thread and the
// profiling runs' helper. The SLAM thread hands over frame intervals (addFrame never waits for the meter)
// and collects per-frame energy with takeResults() or a callback; results lag the frames by up to one meter
// period. Optionally records the raw trace (power_trace.h) and measures an idle baseline before the run.
//
//   PowerSampler sampler(openMeter(config), samplerOptions(config, outDir + "/power.csv"));
//   sampler.measureIdle(config.idleBaselineS);        // optional, blocks for that long
//   sampler.start();
//   ... per frame: sampler.addFrame({index, startNs, endNs}); for (auto& e : sampler.takeResults()) log(e);
//   for (auto& e : sampler.stop()) log(e);            // waits up to the drain timeout for the last samples
//   summary(sampler.totals());

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "power/clock.h"
#include "power/energy_ledger.h"
#include "power/meter.h"
#include "power/power_config.h"
#include "power/power_trace.h"
#include "core/unique_fd.h"

namespace sb::power {

struct SamplerOptions {
  int64_t maxSampleGapNs = 0;            // 0 = max(3 x the meter's nominal period, 1.5 s)
  int64_t drainTimeoutNs = 3'000'000'000;  // stop() waits this long for samples after the last frame
  std::string tracePath;                 // raw trace output (empty = none)
  std::shared_ptr<SegmentStore> traceSegments;  // rotate the trace into these segments (nullptr: one file)
};

// The sampler options a PowerConfig asks for, with the trace written to `tracePath` (may be empty).
SamplerOptions samplerOptions(const PowerConfig& config, const std::string& tracePath = "");

// The gap limit in effect for a meter: options.maxSampleGapNs or the automatic value.
int64_t effectiveMaxGapNs(const SamplerOptions& options, const MeterInfo& meter);

class PowerSampler {
 public:
  using Callback = std::function<void(const FrameEnergy&)>;

  // Takes the meter; the clock must outlive the sampler. Opens the trace file (throws sb::Error naming it).
  explicit PowerSampler(std::unique_ptr<Meter> meter, SamplerOptions options = {},
                        const Clock& clock = monotonicClock());
  ~PowerSampler();  // stop()s if still running; results not taken are dropped
  PowerSampler(const PowerSampler&) = delete;
  PowerSampler& operator=(const PowerSampler&) = delete;

  // Before start(): polls the meter for `seconds` on the calling thread, sets the mean power over that time
  // as the idle baseline and returns it (W). Throws sb::Error when the meter gives too little data.
  double measureIdle(double seconds);
  void setIdleWatts(double watts);

  // Called on the sampler thread for every result, in frame order (set before start(); it must not block).
  // Without a callback results queue up for takeResults().
  void setCallback(Callback callback);

  void start();

  // Thread-safe, non-blocking (a short mutex): the frame's processing interval in CLOCK_MONOTONIC ns.
  void addFrame(const FrameInterval& frame);

  // Results resolved so far (frame order). Thread-safe.
  std::vector<FrameEnergy> takeResults();

  // Waits up to the drain timeout for samples past the last frame, resolves what is left (unknown when no
  // sample came), stops the thread and returns the results not yet taken. Safe to call twice.
  std::vector<FrameEnergy> stop();

  EnergyTotals totals() const;
  MeterStatus meterStatus() const;
  const MeterInfo& meterInfo() const { return info_; }
  int64_t maxGapNs() const { return maxGapNs_; }

 private:
  void run();
  void pollOnce();  // the mutex must not be held
  void waitForMeter();
  void wakeThread();
  void deliver(std::vector<FrameEnergy> results);

  std::unique_ptr<Meter> meter_;
  MeterInfo info_;
  SamplerOptions options_;
  const Clock& clock_;
  int64_t maxGapNs_;
  std::unique_ptr<PowerTraceWriter> trace_;
  Callback callback_;

  mutable std::mutex mutex_;  // guards everything below
  EnergyLedger ledger_;
  std::vector<FrameEnergy> results_;
  MeterStatus status_;
  bool wasConnected_ = true;
  bool everConnected_ = false;
  int64_t startNs_ = 0;
  bool stopping_ = false;
  bool stopped_ = false;

  UniqueFd wakeRead_, wakeWrite_;
  std::thread thread_;
};

}  // namespace sb::power
