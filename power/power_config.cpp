#include "power/power_config.h"

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/json_text.h"
#include "power/meter_registry.h"

namespace sb::power {

namespace {

using nlohmann::json;

// Reads the keys of one JSON object into typed fields; remembers which keys it knows so that finish() can
// refuse the others with the list of known keys.
class Section {
 public:
  Section(const json& j, std::string path, std::string where)
      : j_(j), path_(std::move(path)), where_(std::move(where)) {
    if (!j_.is_object()) throw Error(where_ + ": '" + name() + "' must be a JSON object, got " + j_.dump());
  }

  void text(const char* key, std::string& out) {
    if (const json* v = find(key)) {
      if (!v->is_string()) fail(key, *v, "a string");
      out = v->get<std::string>();
    }
  }
  void integer(const char* key, int& out, int minimum, int maximum) {
    if (const json* v = find(key)) {
      if (!v->is_number_integer()) fail(key, *v, "an integer in " + range(minimum, maximum));
      const auto value = v->get<long long>();
      if (value < minimum || value > maximum) fail(key, *v, "an integer in " + range(minimum, maximum));
      out = static_cast<int>(value);
    }
  }
  void number(const char* key, double& out, double minimum, double maximum) {
    if (const json* v = find(key)) {
      if (!v->is_number() || v->get<double>() < minimum || v->get<double>() > maximum)
        fail(key, *v, "a number in " + range(minimum, maximum));
      out = v->get<double>();
    }
  }
  void texts(const char* key, std::vector<std::string>& out) {
    if (const json* v = find(key)) {
      if (!v->is_array()) fail(key, *v, "an array of strings");
      std::vector<std::string> items;
      for (const json& item : *v) {
        if (!item.is_string()) fail(key, *v, "an array of strings");
        items.push_back(item.get<std::string>());
      }
      out = std::move(items);
    }
  }
  // Calls read(Section&) on the sub-object `key` when present.
  template <typename F>
  void section(const char* key, F read) {
    if (const json* v = find(key)) {
      Section sub(*v, qualified(key), where_);
      read(sub);
      sub.finish();
    }
  }
  void finish() const {
    for (auto it = j_.begin(); it != j_.end(); ++it) {
      if (known_.count(it.key())) continue;
      std::string keys;
      for (const std::string& k : known_) keys += (keys.empty() ? "" : ", ") + k;
      throw Error(where_ + ": unknown key '" + qualified(it.key().c_str()) + "' (known keys" +
                  (path_.empty() ? "" : " of '" + path_ + "'") + ": " + keys + ")");
    }
  }

 private:
  const json* find(const char* key) {
    known_.insert(key);
    auto it = j_.find(key);
    return it == j_.end() ? nullptr : &*it;
  }
  std::string qualified(const char* key) const { return path_.empty() ? key : path_ + "." + key; }
  std::string name() const { return path_.empty() ? "(top level)" : path_; }
  static std::string range(double minimum, double maximum) {
    std::ostringstream s;
    s << "[" << minimum << ", " << maximum << "]";
    return s.str();
  }
  [[noreturn]] void fail(const char* key, const json& v, const std::string& expected) const {
    throw Error(where_ + ": '" + qualified(key) + "' = " + v.dump() + " is not valid; expected " + expected);
  }

  const json& j_;
  std::string path_, where_;
  std::set<std::string> known_;
};

void check(bool ok, const std::string& where, const std::string& what) {
  if (!ok) throw Error(where + ": " + what);
}

const std::set<std::string> kRails{"a15", "a7", "gpu", "mem"};
const std::set<std::string> kChannels{"1", "2", "both", "input"};
const std::set<int> kBauds{9600, 19200, 38400, 57600, 115200, 230400, 460800, 500000, 576000, 921600};

}  // namespace

void validatePowerConfig(const PowerConfig& c, const std::string& where) {
  std::string names;
  for (const std::string& n : meterNames()) names += (names.empty() ? "" : ", ") + n;
  check(isMeterName(c.meter), where, "'meter' = \"" + c.meter + "\" is not a meter; choose one of: " + names);
  check(c.idleBaselineS >= 0.0 && c.idleBaselineS <= 600.0, where, "'idle_baseline_s' must be in [0, 600]");
  check(c.maxSampleGapMs >= 0, where, "'max_sample_gap_ms' must be >= 0 (0 = automatic)");
  check(c.reopenMinMs >= 1 && c.reopenMaxMs >= c.reopenMinMs, where,
        "'reopen_min_ms' must be >= 1 and 'reopen_max_ms' >= 'reopen_min_ms'");
  check(kBauds.count(c.smartpower2.baud) > 0, where,
        "'smartpower2.baud' = " + std::to_string(c.smartpower2.baud) + " is not a supported baud rate");
  check(kBauds.count(c.smartpower3.baud) > 0, where,
        "'smartpower3.baud' = " + std::to_string(c.smartpower3.baud) +
            " is not a supported baud rate (the SmartPower3 offers 9600 ... 921600)");
  check(kChannels.count(c.smartpower3.channel) > 0, where,
        "'smartpower3.channel' = \"" + c.smartpower3.channel + "\" must be \"1\", \"2\", \"both\" or \"input\"");
  for (const std::string& rail : c.ina231.rails)
    check(kRails.count(rail) > 0, where, "'ina231.rails' holds \"" + rail + "\"; rails are a15, a7, gpu, mem");
  check(!c.ina231.rails.empty(), where, "'ina231.rails' must name at least one rail (a15, a7, gpu, mem)");
  check(c.meter != "file" || !c.file.path.empty(), where,
        "meter \"file\" needs 'file.path' (a power trace written by a profiling run)");
  check(!c.smartpower2.device.empty() && !c.smartpower3.device.empty(), where, "serial 'device' paths must be set");
}

PowerConfig parsePowerConfig(const nlohmann::json& j, const PowerConfig& base, const std::string& where) {
  PowerConfig c = base;
  Section top(j, "", where);
  top.text("meter", c.meter);
  top.number("idle_baseline_s", c.idleBaselineS, 0.0, 600.0);
  top.integer("max_sample_gap_ms", c.maxSampleGapMs, 0, 3'600'000);
  top.integer("drain_timeout_ms", c.drainTimeoutMs, 0, 600'000);
  top.integer("reopen_min_ms", c.reopenMinMs, 1, 600'000);
  top.integer("reopen_max_ms", c.reopenMaxMs, 1, 3'600'000);
  top.section("smartpower2", [&](Section& s) {
    s.text("device", c.smartpower2.device);
    s.integer("baud", c.smartpower2.baud, 9600, 921600);
  });
  top.section("smartpower3", [&](Section& s) {
    s.text("device", c.smartpower3.device);
    s.integer("baud", c.smartpower3.baud, 9600, 921600);
    s.text("channel", c.smartpower3.channel);
    s.integer("log_interval_ms", c.smartpower3.logIntervalMs, 5, 1000);
  });
  top.section("smartpower1", [&](Section& s) { s.integer("poll_interval_ms", c.smartpower1.pollIntervalMs, 10, 10000); });
  top.section("ina231", [&](Section& s) {
    s.text("root", c.ina231.root);
    s.texts("rails", c.ina231.rails);
    s.integer("poll_interval_ms", c.ina231.pollIntervalMs, 1, 10000);
  });
  top.section("rapl", [&](Section& s) {
    s.text("root", c.rapl.root);
    s.texts("zones", c.rapl.zones);
    s.integer("poll_interval_ms", c.rapl.pollIntervalMs, 1, 10000);
  });
  top.section("nvml", [&](Section& s) {
    s.text("library", c.nvml.library);
    s.integer("device_index", c.nvml.deviceIndex, 0, 63);
    s.integer("poll_interval_ms", c.nvml.pollIntervalMs, 1, 10000);
  });
  top.section("file", [&](Section& s) { s.text("path", c.file.path); });
  top.finish();
  validatePowerConfig(c, where);
  return c;
}

PowerConfig loadPowerConfig(const std::string& path, const PowerConfig& base) {
  return parsePowerConfig(readJsonFile(path, "power config"), base, path);  // bounded nesting, names the file
}

nlohmann::json powerConfigToJson(const PowerConfig& c) {
  return {{"meter", c.meter},
          {"idle_baseline_s", c.idleBaselineS},
          {"max_sample_gap_ms", c.maxSampleGapMs},
          {"drain_timeout_ms", c.drainTimeoutMs},
          {"reopen_min_ms", c.reopenMinMs},
          {"reopen_max_ms", c.reopenMaxMs},
          {"smartpower2", {{"device", c.smartpower2.device}, {"baud", c.smartpower2.baud}}},
          {"smartpower3",
           {{"device", c.smartpower3.device},
            {"baud", c.smartpower3.baud},
            {"channel", c.smartpower3.channel},
            {"log_interval_ms", c.smartpower3.logIntervalMs}}},
          {"smartpower1", {{"poll_interval_ms", c.smartpower1.pollIntervalMs}}},
          {"ina231", {{"root", c.ina231.root}, {"rails", c.ina231.rails}, {"poll_interval_ms", c.ina231.pollIntervalMs}}},
          {"rapl", {{"root", c.rapl.root}, {"zones", c.rapl.zones}, {"poll_interval_ms", c.rapl.pollIntervalMs}}},
          {"nvml",
           {{"library", c.nvml.library},
            {"device_index", c.nvml.deviceIndex},
            {"poll_interval_ms", c.nvml.pollIntervalMs}}},
          {"file", {{"path", c.file.path}}}};
}

}  // namespace sb::power
