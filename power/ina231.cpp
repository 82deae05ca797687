#include "power/ina231.h"

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/error.h"
#include "power/sysfs_file.h"

namespace sb::power {

namespace {

namespace fs = std::filesystem;

const std::map<std::string, std::string>& railAddresses() {
  static const std::map<std::string, std::string> addresses{
      {"a15", "0040"}, {"mem", "0041"}, {"gpu", "0044"}, {"a7", "0045"}};
  return addresses;
}

class Ina231Meter final : public Meter {
 public:
  Ina231Meter(const Ina231Settings& config, const Clock& clock) : clock_(clock) {
    info_.name = "ina231";
    info_.device = config.root;
    info_.kind = SampleKind::instantaneous;
    info_.nominalPeriodNs = int64_t(config.pollIntervalMs) * 1'000'000;
    std::error_code ec;
    if (!fs::is_directory(config.root, ec))
      throw Error("ina231 meter: '" + config.root +
                  "' does not exist: this is not an ODROID XU3 with the INA231 driver (set ina231.root)");
    for (const std::string& rail : config.rails) {
      const std::string suffix = "-" + railAddresses().at(rail);
      std::string found;
      for (const auto& entry : fs::directory_iterator(config.root, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
          found = entry.path().string();
      }
      if (found.empty())
        throw Error("ina231 meter: no sensor for rail '" + rail + "' (I2C address 0x" + railAddresses().at(rail) +
                    ") under '" + config.root + "'");
      // Enabling needs root; a sensor enabled already (e.g. by a boot script) is left alone.
      if (readSysfsNumber(found + "/enable") != 1.0) writeSysfs(found + "/enable", "1");
      sensors_.push_back(found + "/sensor_W");
    }
    status_.sinceNs = clock_.nowNs();
  }

  const MeterInfo& info() const override { return info_; }
  MeterStatus status() const override { return status_; }

  void poll(std::vector<PowerSample>& out) override {
    double watts = 0.0;
    for (const std::string& path : sensors_) watts += readSysfsNumber(path);
    PowerSample s;
    s.tNs = clock_.nowNs();
    if (s.tNs <= lastNs_) return;
    s.watts = watts;
    lastNs_ = s.tNs;
    ++status_.samples;
    out.push_back(s);
  }

 private:
  const Clock& clock_;
  MeterInfo info_;
  MeterStatus status_;
  std::vector<std::string> sensors_;
  int64_t lastNs_ = 0;
};

}  // namespace

void Ina231Settings::read(ConfigReader& r, bool) {
  r.string("root", root);
  r.strings("rails", rails, {"a15", "a7", "gpu", "mem"}, 1);  // at least one rail
  r.integer("poll_interval_ms", pollIntervalMs, 1, 10000);
}

nlohmann::json Ina231Settings::toJson() const {
  return {{"root", root}, {"rails", rails}, {"poll_interval_ms", pollIntervalMs}};
}

std::unique_ptr<Meter> openIna231(const Ina231Settings& settings, const MeterHostSettings&, const Clock& clock) {
  return std::make_unique<Ina231Meter>(settings, clock);
}

}  // namespace sb::power
