#pragma once
// Hardkernel SmartPower2 (ESP8266 + CP2104 USB serial, 115200 8N1): while its output is on it prints one line
// per second, "V,A,W,Wh\r\n" with three decimals, e.g. "5.102,0.340,1.735,0.000". Boot banners and debug
// lines are skipped; the Wh field usually stays 0 over serial, so it is ignored (the ledger integrates W).

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "core/config_reader.h"
#include "power/clock.h"
#include "power/meter.h"
#include "power/serial_line_meter.h"

namespace sb::power {

// The "smartpower2" section of the power config (config/README.md).
struct SmartPower2Settings {
  std::string device = "/dev/ttyUSB0";  // CP2104 USB serial; a /dev/serial/by-id/ link survives replugging
  int baud = 115200;                    // 8N1

  void read(ConfigReader& r, bool selected);  // keys: device, baud
  nlohmann::json toJson() const;
};

// The line parser (exposed for tests): exactly four unsigned decimal fields within the meter's range.
LineResult parseSmartPower2Line(std::string_view line, LineReading& reading);

std::unique_ptr<Meter> openSmartPower2(const SmartPower2Settings& settings, const MeterHostSettings& host,
                                       const Clock& clock);

}  // namespace sb::power
