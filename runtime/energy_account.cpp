#include "runtime/energy_account.h"

#include <spdlog/spdlog.h>

#include "power/energy_json.h"
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

nlohmann::json EnergyAccount::totals() const {
  nlohmann::json j = power::energyTotalsJson(sampler_.totals(), unknownReasons_);
  j["meter"] = sampler_.meterInfo().name;
  j["device"] = sampler_.meterInfo().device;
  return j;
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
