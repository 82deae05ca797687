#pragma once
// The first Hardkernel SmartPower: USB HID 04d8:003f, read through libusb. Each poll sends the data request
// (report 0x37) and parses the ASCII reply (smartpower1_reply.h). The device needs write access: without it
// opening fails with an error that names the udev rule to install.

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "core/config_reader.h"
#include "power/clock.h"
#include "power/meter.h"

namespace sb::power {

// The "smartpower1" section of the power config (config/README.md).
struct SmartPower1Settings {
  int pollIntervalMs = 100;             // request period for the HID report 0x37

  void read(ConfigReader& r, bool selected);  // key: poll_interval_ms
  nlohmann::json toJson() const;
};

constexpr uint16_t kSmartPower1Vendor = 0x04d8;
constexpr uint16_t kSmartPower1Product = 0x003f;

// The udev rule that gives the plugdev group access (quoted in the access-denied error and power/README.md).
const char* smartPower1UdevRule();

// The message for a failed open: `error` plus, when access was denied, how to install the udev rule.
std::string smartPower1OpenError(const std::string& error, bool accessDenied);

std::unique_ptr<Meter> openSmartPower1(const SmartPower1Settings& settings, const MeterHostSettings& host,
                                       const Clock& clock);

}  // namespace sb::power
