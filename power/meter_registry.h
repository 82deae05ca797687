#pragma once
// Meters by name. Adding a meter: its file pair (the driver and its settings struct) plus one line in
// meter_registry.cpp. Each registered meter parses its own section of the power config with the one config
// reader (core/config_reader.h); power_config.cpp asks this registry for the parsers, never the other way.

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/config_reader.h"
#include "power/clock.h"
#include "power/meter.h"

namespace sb::power {

struct MeterType {
  std::string name;  // the config's "meter" value and the name of its settings section
  // Reads and checks the meter's section (`reader` stands on it; the caller calls finish()) and returns the
  // complete settings, defaults filled in. `selected`: this is the meter the config chooses (settings it
  // cannot run without are required then). Empty for a meter without settings.
  std::function<nlohmann::json(ConfigReader& reader, bool selected)> readSettings;
  // Opens the meter from its section. Throws sb::Error (naming the device and the fix) when it cannot.
  std::function<std::unique_ptr<Meter>(ConfigReader& settings, const MeterHostSettings& host,
                                       const Clock& clock)>
      open;
};

// A registry entry for a meter whose settings struct has read(ConfigReader&, bool) and toJson().
template <typename Settings>
MeterType meterType(const char* name,
                    std::unique_ptr<Meter> (*open)(const Settings&, const MeterHostSettings&, const Clock&)) {
  MeterType t;
  t.name = name;
  t.readSettings = [](ConfigReader& reader, bool selected) {
    Settings s;
    s.read(reader, selected);
    return s.toJson();
  };
  t.open = [open](ConfigReader& reader, const MeterHostSettings& host, const Clock& clock) {
    Settings s;
    s.read(reader, true);
    reader.finish();
    return open(s, host, clock);
  };
  return t;
}

// The registered meters, in registry order; nullptr for an unknown name.
const std::vector<MeterType>& meterTypes();
const MeterType* findMeterType(const std::string& name);

const std::vector<std::string>& meterNames();
bool isMeterName(const std::string& name);

}  // namespace sb::power
