#pragma once
// The INA231 power sensors of the ODROID XU3 (A15 cores, A7 cores, GPU and memory rails), read through the
// Hardkernel kernel driver's sysfs: <root>/<bus>-<addr>/enable (write 1 to start measuring) and sensor_W.
// Rails are found by I2C address (a15 0x40, mem 0x41, gpu 0x44, a7 0x45) whatever the bus number; the
// sample is the sum of the configured rails. The root is configurable so tests use a fake tree.

#include <memory>

#include "power/clock.h"
#include "power/meter.h"
#include "power/power_config.h"

namespace sb::power {

std::unique_ptr<Meter> openIna231(const PowerConfig& config, const Clock& clock);

}  // namespace sb::power
