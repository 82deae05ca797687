#include "power/meter_registry.h"

#include <algorithm>

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

MeterType noMeter() {
  MeterType t;
  t.name = "none";
  t.open = [](ConfigReader&, const MeterHostSettings&, const Clock&) { return std::make_unique<NoMeter>(); };
  return t;
}

}  // namespace

const std::vector<MeterType>& meterTypes() {
  static const std::vector<MeterType> types = {
      meterType("smartpower2", openSmartPower2),
      meterType("smartpower3", openSmartPower3),
      meterType("smartpower1", openSmartPower1),
      meterType("ina231", openIna231),
      meterType("rapl", openRapl),
      meterType("nvml", openNvml),
      meterType("file", openFileMeter),
      noMeter(),
  };
  return types;
}

const MeterType* findMeterType(const std::string& name) {
  for (const MeterType& t : meterTypes())
    if (t.name == name) return &t;
  return nullptr;
}

const std::vector<std::string>& meterNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const MeterType& t : meterTypes()) n.push_back(t.name);
    return n;
  }();
  return names;
}

bool isMeterName(const std::string& name) {
  return findMeterType(name) != nullptr;
}

}  // namespace sb::power
