#pragma once
// The power-metering configuration: one typed struct, parsed and validated once. config/power.json is the
// documented default (key table in config/README.md). Only the section of the chosen meter is used; every
// section is still validated (by its meter's own parser, meter_registry.h) so that a typo never waits for the
// day someone switches meters.

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "power/clock.h"
#include "power/meter.h"

namespace sb::power {

struct PowerConfig {
  std::string meter = "none";           // a registered meter (meterNames() in meter_registry.h), or "none"
  double idleBaselineS = 0.0;           // s: measure idle power this long before the run (0 = no baseline)
  int maxSampleGapMs = 0;               // ms: samples farther apart enclose a gap; 0 = max(3 periods, 1500)
  int drainTimeoutMs = 3000;            // ms: at stop, wait this long for a sample after the last frame
  int reopenMinMs = 250;                // ms: first retry after a device is lost; doubles up to reopenMaxMs
  int reopenMaxMs = 8000;
  // Each meter's settings section by meter name, as the meter's own parser (its file pair) reads it; a meter
  // without an entry has its defaults.
  nlohmann::json meters = nlohmann::json::object();

  MeterHostSettings host() const { return {reopenMinMs, reopenMaxMs}; }
};

// Reads `j` on top of `base` with the config reader; each meter's section goes to that meter's parser. Unknown
// keys (at any level), wrong types and out-of-range values throw sb::Error naming `where`, the key path (e.g.
// "ina231.rails"), the value and what is allowed.
PowerConfig parsePowerConfig(const nlohmann::json& j, const PowerConfig& base = {},
                             const std::string& where = "power config");

// Reads a JSON file (see parsePowerConfig); I/O and syntax errors name the file.
PowerConfig loadPowerConfig(const std::string& path, const PowerConfig& base = {});

// The whole config as JSON (the keys parsePowerConfig reads, every meter's section complete).
nlohmann::json powerConfigToJson(const PowerConfig& config);

// Opens the meter named config.meter with its settings section. Throws sb::Error (naming the device and the
// fix) when it cannot be opened. The clock must outlive the meter.
std::unique_ptr<Meter> openMeter(const PowerConfig& config, const Clock& clock = monotonicClock());

}  // namespace sb::power
