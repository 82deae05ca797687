#pragma once
// NVIDIA GPUs through NVML, loaded at run time with dlopen (no build-time dependency on the driver). Uses the
// total-energy counter (millijoules, Volta and newer) as interval-average samples; GPUs without it fall back
// to the instantaneous power reading. Without the library the meter fails with an error that says so.

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/config_reader.h"
#include "power/clock.h"
#include "power/meter.h"

namespace sb::power {

// The "nvml" section of the power config (config/README.md).
struct NvmlSettings {
  std::string library = "libnvidia-ml.so.1";  // loaded with dlopen at run time
  int deviceIndex = 0;
  int pollIntervalMs = 20;

  void read(ConfigReader& r, bool selected);  // keys: library, device_index, poll_interval_ms
  nlohmann::json toJson() const;
};

std::unique_ptr<Meter> openNvml(const NvmlSettings& settings, const MeterHostSettings& host, const Clock& clock);

}  // namespace sb::power
