#pragma once
// Hardkernel SmartPower2 (ESP8266 + CP2104 USB serial, 115200 8N1): while its output is on it prints one line
// per second, "V,A,W,Wh\r\n" with three decimals, e.g. "5.102,0.340,1.735,0.000". Boot banners and debug
// lines are skipped; the Wh field usually stays 0 over serial, so it is ignored (the ledger integrates W).

#include <memory>
#include <string_view>

#include "power/clock.h"
#include "power/meter.h"
#include "power/power_config.h"
#include "power/serial_line_meter.h"

namespace sb::power {

// The line parser (exposed for tests): exactly four unsigned decimal fields within the meter's range.
LineResult parseSmartPower2Line(std::string_view line, LineReading& reading);

std::unique_ptr<Meter> openSmartPower2(const PowerConfig& config, const Clock& clock);

}  // namespace sb::power
