#pragma once
// The reply of the first SmartPower (USB HID 04d8:003f) to the data request 0x37, separated from the USB code
// so that tests can feed recorded replies. The reply is a 64-byte report that echoes 0x37 ('7') and holds
// ASCII text such as "7 5.000V  0.302 A 1.510W  0.012Wh" (fixed-width fields; "-.---" while the output is
// off). Layout as documented by energymon's hosp library (energymon/hosp, src/hosp.c) and TUD-OS/OdroidReader.

#include <cstddef>
#include <cstdint>
#include <optional>

namespace sb::power {

constexpr uint8_t kSmartPower1RequestData = 0x37;

struct SmartPower1Reading {
  double volts = 0.0;
  double amps = 0.0;    // 0 while the output is off ("-.---")
  double watts = 0.0;   // 0 while the output is off
  bool outputOn = false;
};

// Nothing when the report is not a data reply (wrong echo byte, missing fields, non-ASCII text).
std::optional<SmartPower1Reading> parseSmartPower1Reply(const uint8_t* report, size_t size);

}  // namespace sb::power
