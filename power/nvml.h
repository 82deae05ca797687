#pragma once
// NVIDIA GPUs through NVML, loaded at run time with dlopen (no build-time dependency on the driver). Uses the
// total-energy counter (millijoules, Volta and newer) as interval-average samples; GPUs without it fall back
// to the instantaneous power reading. Without the library the meter fails with an error that says so.

#include <memory>

#include "power/clock.h"
#include "power/meter.h"
#include "power/power_config.h"

namespace sb::power {

std::unique_ptr<Meter> openNvml(const PowerConfig& config, const Clock& clock);

}  // namespace sb::power
