#include "power/power_config.h"

#include "core/config_reader.h"
#include "core/error.h"
#include "power/meter_registry.h"

namespace sb::power {

namespace {

using nlohmann::json;

// `type`'s section of `c` (empty when absent: the meter's defaults).
json sectionOf(const PowerConfig& c, const MeterType& type) {
  const auto it = c.meters.find(type.name);
  return it == c.meters.end() ? json::object() : *it;
}

// The meter-independent keys, checked together (a config built in code has not been through the reader).
void validateHost(const PowerConfig& c, const std::string& where) {
  std::string names;
  for (const std::string& n : meterNames()) names += (names.empty() ? "\"" : ", \"") + n + "\"";
  const auto fail = [&](const std::string& what) { throw Error(where + ": " + what); };
  if (!isMeterName(c.meter))
    fail("'meter' = \"" + c.meter + "\" is not allowed: expected one of " + names + "; fix the value");
  if (!(c.idleBaselineS >= 0.0 && c.idleBaselineS <= 600.0))
    fail("'idle_baseline_s' = " + std::to_string(c.idleBaselineS) + " is not allowed: expected [0, 600] s");
  if (c.maxSampleGapMs < 0)
    fail("'max_sample_gap_ms' = " + std::to_string(c.maxSampleGapMs) +
         " is not allowed: expected >= 0 (0 = automatic)");
  if (c.reopenMinMs < 1 || c.reopenMaxMs < c.reopenMinMs)
    fail("'reopen_max_ms' = " + std::to_string(c.reopenMaxMs) +
         " is not allowed: expected 'reopen_min_ms' (" + std::to_string(c.reopenMinMs) +
         ", at least 1) or more; fix the values");
}

}  // namespace

PowerConfig parsePowerConfig(const json& j, const PowerConfig& base, const std::string& where) {
  PowerConfig c = base;
  ConfigReader top(j, where);
  top.string("meter", c.meter);
  top.number("idle_baseline_s", c.idleBaselineS, 0.0, 600.0);
  top.integer("max_sample_gap_ms", c.maxSampleGapMs, 0, 3'600'000);
  top.integer("drain_timeout_ms", c.drainTimeoutMs, 0, 600'000);
  top.integer("reopen_min_ms", c.reopenMinMs, 1, 600'000);
  top.integer("reopen_max_ms", c.reopenMaxMs, 1, 3'600'000);
  // Each meter's section, on top of the base's, goes to the meter's own parser.
  std::vector<std::pair<const MeterType*, json>> sections;
  for (const MeterType& type : meterTypes()) {
    if (!type.readSettings) continue;
    json section = sectionOf(c, type);
    if (const json* v = top.object(type.name))
      for (auto it = v->begin(); it != v->end(); ++it) section[it.key()] = it.value();
    sections.emplace_back(&type, std::move(section));
  }
  top.finish();
  validateHost(c, where);
  for (const auto& [type, section] : sections) {
    ConfigReader r(section, where, type->name);
    c.meters[type->name] = type->readSettings(r, c.meter == type->name);
    r.finish();
  }
  return c;
}

PowerConfig loadPowerConfig(const std::string& path, const PowerConfig& base) {
  return parsePowerConfig(readJsonConfig(path, "power config"), base,
                          path);  // bounded nesting, names the file
}

json powerConfigToJson(const PowerConfig& c) {
  json j = {{"meter", c.meter},
            {"idle_baseline_s", c.idleBaselineS},
            {"max_sample_gap_ms", c.maxSampleGapMs},
            {"drain_timeout_ms", c.drainTimeoutMs},
            {"reopen_min_ms", c.reopenMinMs},
            {"reopen_max_ms", c.reopenMaxMs}};
  for (const MeterType& type : meterTypes()) {
    if (!type.readSettings) continue;
    ConfigReader r(sectionOf(c, type), "power config", type.name);
    j[type.name] = type.readSettings(r, false);
  }
  return j;
}

std::unique_ptr<Meter> openMeter(const PowerConfig& config, const Clock& clock) {
  const MeterType* type = findMeterType(config.meter);
  if (!type) validateHost(config, "power config");  // throws, listing the meters
  ConfigReader settings(sectionOf(config, *type), "power config", type->name);
  return type->open(settings, config.host(), clock);
}

}  // namespace sb::power
