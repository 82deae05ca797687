#pragma once
// Intel/AMD RAPL through the Linux powercap sysfs: <root>/<zone>/energy_uj, a microjoule counter that wraps to
// 0 after max_energy_range_uj. Samples are interval averages (see energy_counter.h), summed over the zones.
// Default zones: every top-level package zone (intel-rapl:N; sub-zones such as intel-rapl:0:0 are parts of
// their package and would be counted twice). Since Linux 5.10 energy_uj is readable by root only.

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/config_reader.h"
#include "power/clock.h"
#include "power/meter.h"

namespace sb::power {

// The "rapl" section of the power config (config/README.md).
struct RaplSettings {
  std::string root = "/sys/class/powercap";
  std::vector<std::string> zones;       // e.g. ["intel-rapl:0"]; empty = every top-level package zone
  int pollIntervalMs = 10;

  void read(ConfigReader& r, bool selected);  // keys: root, zones, poll_interval_ms
  nlohmann::json toJson() const;
};

std::unique_ptr<Meter> openRapl(const RaplSettings& settings, const MeterHostSettings& host, const Clock& clock);

}  // namespace sb::power
