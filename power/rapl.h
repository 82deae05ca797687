#pragma once
// Intel/AMD RAPL through the Linux powercap sysfs: <root>/<zone>/energy_uj, a microjoule counter that wraps to
// 0 after max_energy_range_uj. Samples are interval averages (see energy_counter.h), summed over the zones.
// Default zones: every top-level package zone (intel-rapl:N; sub-zones such as intel-rapl:0:0 are parts of
// their package and would be counted twice). Since Linux 5.10 energy_uj is readable by root only.

#include <memory>

#include "power/clock.h"
#include "power/meter.h"
#include "power/power_config.h"

namespace sb::power {

std::unique_ptr<Meter> openRapl(const PowerConfig& config, const Clock& clock);

}  // namespace sb::power
