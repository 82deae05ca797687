#pragma once
// The INA231 power sensors of the ODROID XU3 (A15 cores, A7 cores, GPU and memory rails), read through the
// Hardkernel kernel driver's sysfs: <root>/<bus>-<addr>/enable (write 1 to start measuring) and sensor_W.
// Rails are found by I2C address (a15 0x40, mem 0x41, gpu 0x44, a7 0x45) whatever the bus number; the
// sample is the sum of the configured rails. The root is configurable so tests use a fake tree.

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/config_reader.h"
#include "power/clock.h"
#include "power/meter.h"

namespace sb::power {

// The "ina231" section of the power config (config/README.md).
struct Ina231Settings {
  std::string root = "/sys/bus/i2c/drivers/INA231";
  std::vector<std::string> rails{"a15", "a7", "gpu", "mem"};  // summed; a15=0x40, mem=0x41, gpu=0x44, a7=0x45
  int pollIntervalMs = 50;

  void read(ConfigReader& r, bool selected);  // keys: root, rails, poll_interval_ms
  nlohmann::json toJson() const;
};

std::unique_ptr<Meter> openIna231(const Ina231Settings& settings, const MeterHostSettings& host, const Clock& clock);

}  // namespace sb::power
