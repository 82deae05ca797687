#pragma once
// Joules per frame for a run: an output that feeds every frame's processing interval (FrameRecord::startMonoNs
// .. endMonoNs) to a PowerSampler (power/power_sampler.h) and writes the results to energy.jsonl as they
// resolve (they lag the frames by up to one meter period), the raw trace to power.csv beside it for offline
// re-accounting (`slambooster energy`), and the totals for summary.json.
//
//   auto energy = sb::makeEnergySink(sb::power::loadPowerConfig(path), outDir);   // nullptr for meter "none"
//   energy->setCallback([&](const sb::power::FrameEnergy& e) { ... });           // optional: each result
//   runner.addSink(std::move(energy));  ... per frame runner.step(frame) ...
//   summary->setExtra("energy", sink.finish());                                   // waits for the last samples

#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "power/power_config.h"
#include "power/power_sampler.h"
#include "runtime/line_file.h"
#include "runtime/output_sink.h"

namespace sb {

class EnergySink : public OutputSink {
 public:
  using Callback = std::function<void(const power::FrameEnergy&)>;

  // Starts `sampler` (already configured; idle baseline measured if wanted). Writes `energyPath`.
  EnergySink(std::unique_ptr<power::PowerSampler> sampler, const std::string& energyPath);
  ~EnergySink() override;

  // Called on the thread that drives the runner, for every resolved frame in order (set before the first frame).
  void setCallback(Callback callback) { callback_ = std::move(callback); }

  void onFrame(const FrameRecord& record) override;  // never waits for the meter
  void flush() override;

  // End of run: waits up to the sampler's drain timeout for samples after the last frame, writes the rest,
  // and returns the totals (power::energyTotalsJson plus "meter" and "device"). Safe to call twice.
  nlohmann::json finish();

  const power::PowerSampler& sampler() const { return *sampler_; }

 private:
  void write(const std::vector<power::FrameEnergy>& results);

  std::unique_ptr<power::PowerSampler> sampler_;
  std::string path_;
  LineFile out_;
  Callback callback_;
  std::map<std::string, size_t> unknownReasons_;
  bool finished_ = false;
};

// The sink for `config` writing energy.jsonl and power.csv into `dir`, or nullptr when config.meter is "none".
// Opens the meter (throws sb::Error naming the device and what to do) and measures the idle baseline when
// config.idleBaselineS > 0 (blocks that long).
std::unique_ptr<EnergySink> makeEnergySink(const power::PowerConfig& config, const std::string& dir);

}  // namespace sb
