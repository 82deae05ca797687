#pragma once
// Hardkernel SmartPower3 (ESP32, USB serial, 921600 baud by default here; 5 ms - 1 s logging interval).
//
// Line format, from the firmware's logTask() in hardkernel/smartpower3 (smartpower3/smartpower3.ino, buffer
// sizes in smartpower3/wifi_manager.h) and the field list of connorimes/osp3 (inc/osp3.h): 81 bytes,
// 17 comma-separated fields, "\r\n"-terminated:
//
//   ms(10 digits), input mV(5), input mA(4), input mW(5), low-input flag(1),
//   ch1 mV(5), ch1 mA(4), ch1 mW(5), ch1 on/off(1), ch1 interrupts(2 hex),
//   ch2 mV(5), ch2 mA(4), ch2 mW(5), ch2 on/off(1), ch2 interrupts(2 hex),
//   checksum8 two's complement(2 hex), checksum8 xor(2 hex)
//
// Both checksums cover every byte before the first checksum field (the 74 bytes up to and including the comma
// that follows the ch2 interrupts): the first is the two's complement of the byte sum modulo 256, the second
// the XOR of the bytes; both printed as two lowercase hex digits. Lines whose checksums do not match are
// refused (counted in MeterStatus::checksumErrors); the device's ms counter spaces lines read in one batch.

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "core/config_reader.h"
#include "power/clock.h"
#include "power/meter.h"
#include "power/serial_line_meter.h"

namespace sb::power {

// The "smartpower3" section of the power config (config/README.md).
struct SmartPower3Settings {
  std::string device = "/dev/ttyUSB0";
  int baud = 921600;                    // must match the device's serial setting
  std::string channel = "1";            // "1", "2" (output channels), "both" (sum of 1 and 2), "input"
  int logIntervalMs = 10;               // the device's logging interval (5..1000): nominal sample period

  // Reads and checks the section's keys (device, baud, channel, log_interval_ms).
  void read(ConfigReader& r, bool selected);
  nlohmann::json toJson() const;
};

enum class SmartPower3Channel { output1, output2, both, input };

// "1", "2", "both", "input" (validated by SmartPower3Settings::read).
SmartPower3Channel parseSmartPower3Channel(const std::string& name);

// The line parser (exposed for tests).
LineResult parseSmartPower3Line(std::string_view line, SmartPower3Channel channel, LineReading& reading);

std::unique_ptr<Meter> openSmartPower3(const SmartPower3Settings& settings, const MeterHostSettings& host,
                                       const Clock& clock);

}  // namespace sb::power
