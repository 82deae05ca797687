#pragma once
// The power-metering configuration: one typed struct, parsed and validated once. config/power.json is the
// documented default (key table in config/README.md). Only the section of the chosen meter is used; every
// section is still validated so that a typo never waits for the day someone switches meters.

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

namespace sb::power {

struct SmartPower2Config {
  std::string device = "/dev/ttyUSB0";  // CP2104 USB serial; a /dev/serial/by-id/ link survives replugging
  int baud = 115200;                    // 8N1
};

struct SmartPower3Config {
  std::string device = "/dev/ttyUSB0";
  int baud = 921600;                    // must match the device's serial setting
  std::string channel = "1";            // "1", "2" (output channels), "both" (sum of 1 and 2), "input"
  int logIntervalMs = 10;               // the device's logging interval (5..1000): nominal sample period
};

struct SmartPower1Config {
  int pollIntervalMs = 100;             // request period for the HID report 0x37
};

struct Ina231Config {
  std::string root = "/sys/bus/i2c/drivers/INA231";
  std::vector<std::string> rails{"a15", "a7", "gpu", "mem"};  // summed; a15=0x40, mem=0x41, gpu=0x44, a7=0x45
  int pollIntervalMs = 50;
};

struct RaplConfig {
  std::string root = "/sys/class/powercap";
  std::vector<std::string> zones;       // e.g. ["intel-rapl:0"]; empty = every top-level package zone
  int pollIntervalMs = 10;
};

struct NvmlConfig {
  std::string library = "libnvidia-ml.so.1";  // loaded with dlopen at run time
  int deviceIndex = 0;
  int pollIntervalMs = 20;
};

struct FileMeterConfig {
  std::string path;                     // a power trace CSV (power_trace.h); required for meter "file"
};

struct PowerConfig {
  std::string meter = "none";           // a registered meter (meter_registry.h): smartpower2, smartpower3,
                                        // smartpower1, ina231, rapl, nvml, file, none
  double idleBaselineS = 0.0;           // s: measure idle power this long before the run (0 = no baseline)
  int maxSampleGapMs = 0;               // ms: samples farther apart enclose a gap; 0 = max(3 periods, 1500)
  int drainTimeoutMs = 3000;            // ms: at stop, wait this long for a sample after the last frame
  int reopenMinMs = 250;                // ms: first retry after a device is lost; doubles up to reopenMaxMs
  int reopenMaxMs = 8000;
  SmartPower2Config smartpower2;
  SmartPower3Config smartpower3;
  SmartPower1Config smartpower1;
  Ina231Config ina231;
  RaplConfig rapl;
  NvmlConfig nvml;
  FileMeterConfig file;
};

// Reads `j` on top of `base`. Unknown keys (at any level), wrong types and out-of-range values throw sb::Error
// naming `where`, the key path (e.g. "smartpower3.channel"), the value and what is allowed.
PowerConfig parsePowerConfig(const nlohmann::json& j, const PowerConfig& base = {},
                             const std::string& where = "power config");

// Reads a JSON file (see parsePowerConfig); I/O and syntax errors name the file.
PowerConfig loadPowerConfig(const std::string& path, const PowerConfig& base = {});

// Throws sb::Error for values out of range (used by parsePowerConfig; call it after building a config in code).
void validatePowerConfig(const PowerConfig& config, const std::string& where = "power config");

// The whole config as JSON (the keys parsePowerConfig reads).
nlohmann::json powerConfigToJson(const PowerConfig& config);

}  // namespace sb::power
