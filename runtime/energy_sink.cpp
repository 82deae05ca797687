#include "runtime/energy_sink.h"

#include <spdlog/spdlog.h>

#include "core/error.h"
#include "power/energy_json.h"
#include "power/meter_registry.h"

namespace sb {

EnergySink::EnergySink(std::unique_ptr<power::PowerSampler> sampler, const std::string& energyPath)
    : sampler_(std::move(sampler)), path_(energyPath), out_(energyPath, "per-frame energy log") {
  if (!sampler_) throw Error("EnergySink: no sampler given");
  sampler_->start();
}

EnergySink::~EnergySink() {
  try {
    finish();
  } catch (const std::exception& e) {
    spdlog::error("energy log '{}': {}", path_, e.what());
  }
}

void EnergySink::onFrame(const FrameRecord& record) {
  sampler_->addFrame({record.result.frame, record.startMonoNs, record.endMonoNs});
  write(sampler_->takeResults());
}

void EnergySink::flush() {}  // every line is written as its frame's energy is known

void EnergySink::write(const std::vector<power::FrameEnergy>& results) {
  for (const power::FrameEnergy& e : results) {
    if (!e.known) ++unknownReasons_[e.unknownReason];
    out_.append(power::frameEnergyJson(e).dump() + "\n");  // one write: a crash leaves whole lines
    if (callback_) callback_(e);
  }
}

nlohmann::json EnergySink::finish() {
  if (!finished_) {
    finished_ = true;
    write(sampler_->stop());
    flush();
  }
  nlohmann::json j = power::energyTotalsJson(sampler_->totals(), unknownReasons_);
  j["meter"] = sampler_->meterInfo().name;
  j["device"] = sampler_->meterInfo().device;
  return j;
}

std::unique_ptr<EnergySink> makeEnergySink(const power::PowerConfig& config, const std::string& dir) {
  if (config.meter == "none") return nullptr;
  auto sampler = std::make_unique<power::PowerSampler>(power::openMeter(config),
                                                       power::samplerOptions(config, dir + "/power.csv"));
  if (config.idleBaselineS > 0) {
    spdlog::info("measuring idle power for {} s before the run", config.idleBaselineS);
    const double watts = sampler->measureIdle(config.idleBaselineS);
    spdlog::info("idle baseline {:.3f} W", watts);
  }
  return std::make_unique<EnergySink>(std::move(sampler), dir + "/energy.jsonl");
}

}  // namespace sb
