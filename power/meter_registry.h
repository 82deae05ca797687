#pragma once
// Meters by name. Adding a meter: its file pair plus one line in meter_registry.cpp.

#include <memory>
#include <string>
#include <vector>

#include "power/clock.h"
#include "power/meter.h"
#include "power/power_config.h"

namespace sb::power {

// Opens the meter named config.meter with its section of the config. Throws sb::Error (naming the device and
// the fix) when it cannot be opened. The clock must outlive the meter.
std::unique_ptr<Meter> openMeter(const PowerConfig& config, const Clock& clock = monotonicClock());

const std::vector<std::string>& meterNames();
bool isMeterName(const std::string& name);

}  // namespace sb::power
