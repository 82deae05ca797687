#include "runtime/energy_account.h"

#include <spdlog/spdlog.h>

#include "power/meter_registry.h"

namespace sb {

EnergyAccount::EnergyAccount(power::PowerSampler& sampler) : sampler_(sampler) {}

std::vector<power::FrameEnergy> EnergyAccount::add(const FrameRecord& record) {
  sampler_.addFrame({record.result.frame, record.startMonoNs, record.endMonoNs});
  return counted(sampler_.takeResults());
}

std::vector<power::FrameEnergy> EnergyAccount::drain() {
  if (drained_) return {};
  drained_ = true;
  return counted(sampler_.stop());
}

std::vector<power::FrameEnergy> EnergyAccount::counted(std::vector<power::FrameEnergy> results) {
  for (const power::FrameEnergy& e : results)
    if (!e.known) ++unknownReasons_[e.unknownReason];
  return results;
}

EnergySummary EnergyAccount::totals() const {
  const power::EnergyTotals t = sampler_.totals();
  EnergySummary e;
  e.meter = sampler_.meterInfo().name;
  e.device = sampler_.meterInfo().device;
  e.frames = t.frames;
  e.knownFrames = t.knownFrames;
  e.unknownFrames = t.unknownFrames;
  e.joules = t.joules;
  e.joulesAboveIdle = t.joulesAboveIdle;
  e.seconds = t.seconds;
  e.idleWatts = t.idleWatts;
  e.joulesPerFrame = t.joulesPerFrame();
  e.meanWatts = t.meanWatts();
  e.spanSeconds = t.spanSeconds;
  e.spanKnownSeconds = t.spanKnownSeconds;
  e.spanJoules = t.spanJoules;
  e.spanMeanWatts = t.spanMeanWatts();
  e.unknownReasons = unknownReasons_;
  return e;
}

std::unique_ptr<power::PowerSampler> openSampler(const power::PowerConfig& config, const std::string& dir,
                                                 std::shared_ptr<SegmentStore> segments) {
  if (config.meter == "none") return nullptr;
  power::SamplerOptions options = power::samplerOptions(config, dir + "/power.csv");
  options.traceSegments = std::move(segments);
  auto sampler = std::make_unique<power::PowerSampler>(power::openMeter(config), std::move(options));
  if (config.idleBaselineS > 0) {
    spdlog::info("measuring idle power for {} s before the run", config.idleBaselineS);
    const double watts = sampler->measureIdle(config.idleBaselineS);
    spdlog::info("idle baseline {:.3f} W", watts);
  }
  return sampler;
}

}  // namespace sb
