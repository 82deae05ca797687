#include "power/meter_registry.h"

#include <algorithm>

#include "core/error.h"
#include "power/file_meter.h"
#include "power/ina231.h"
#include "power/nvml.h"
#include "power/rapl.h"
#include "power/smartpower1.h"
#include "power/smartpower2.h"
#include "power/smartpower3.h"

namespace sb::power {

namespace {

// "none": no device; every frame's energy is unknown.
class NoMeter final : public Meter {
 public:
  NoMeter() {
    info_.name = "none";
    info_.nominalPeriodNs = 1'000'000'000;
    status_.connected = false;
    status_.message = "no power meter configured (meter \"none\")";
  }
  const MeterInfo& info() const override { return info_; }
  void poll(std::vector<PowerSample>&) override {}
  MeterStatus status() const override { return status_; }

 private:
  MeterInfo info_;
  MeterStatus status_;
};

std::unique_ptr<Meter> openNone(const PowerConfig&, const Clock&) { return std::make_unique<NoMeter>(); }

using Factory = std::unique_ptr<Meter> (*)(const PowerConfig&, const Clock&);
struct Entry {
  const char* name;
  Factory open;
};

const std::vector<Entry>& registry() {
  static const std::vector<Entry> entries = {
      {"smartpower2", openSmartPower2},
      {"smartpower3", openSmartPower3},
      {"smartpower1", openSmartPower1},
      {"ina231", openIna231},
      {"rapl", openRapl},
      {"nvml", openNvml},
      {"file", openFileMeter},
      {"none", openNone},
  };
  return entries;
}

}  // namespace

std::unique_ptr<Meter> openMeter(const PowerConfig& config, const Clock& clock) {
  for (const Entry& e : registry())
    if (config.meter == e.name) return e.open(config, clock);
  validatePowerConfig(config);  // throws, listing the meters
  throw Error("unknown meter '" + config.meter + "'");
}

const std::vector<std::string>& meterNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const Entry& e : registry()) n.emplace_back(e.name);
    return n;
  }();
  return names;
}

bool isMeterName(const std::string& name) {
  return std::find(meterNames().begin(), meterNames().end(), name) != meterNames().end();
}

}  // namespace sb::power
