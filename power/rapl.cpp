#include "power/rapl.h"

#include <algorithm>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "core/error.h"
#include "power/energy_counter.h"
#include "power/sysfs_file.h"

namespace sb::power {

namespace {

namespace fs = std::filesystem;

struct Zone {
  std::string energyPath;
  uint64_t maxRange = 0;
  uint64_t last = 0;
};

class RaplMeter final : public Meter {
 public:
  RaplMeter(const RaplSettings& config, const Clock& clock) : clock_(clock), counter_(1e-6) {
    info_.name = "rapl";
    info_.kind = SampleKind::intervalAverage;
    info_.nominalPeriodNs = int64_t(config.pollIntervalMs) * 1'000'000;
    std::vector<std::string> names = config.zones;
    std::error_code ec;
    if (!fs::is_directory(config.root, ec))
      throw Error("rapl meter: '" + config.root + "' does not exist (no powercap support; set rapl.root)");
    if (names.empty()) {
      const std::regex package("[a-z]+-rapl:[0-9]+");
      for (const auto& entry : fs::directory_iterator(config.root, ec))
        if (std::regex_match(entry.path().filename().string(), package)) names.push_back(entry.path().filename());
      std::sort(names.begin(), names.end());
      if (names.empty())
        throw Error("rapl meter: no RAPL package zone (intel-rapl:N) under '" + config.root +
                    "': load the intel_rapl_msr module, or this CPU has no RAPL");
    }
    for (const std::string& name : names) {
      Zone z;
      const std::string dir = config.root + "/" + name;
      z.energyPath = dir + "/energy_uj";
      z.maxRange = readSysfsCounter(dir + "/max_energy_range_uj");
      z.last = readSysfsCounter(z.energyPath);  // also checks access now rather than at the first poll
      zones_.push_back(z);
      info_.device += (info_.device.empty() ? "" : ",") + dir;
    }
    counter_.update(clock_.nowNs(), total_);
    status_.sinceNs = clock_.nowNs();
  }

  const MeterInfo& info() const override { return info_; }
  MeterStatus status() const override { return status_; }

  void poll(std::vector<PowerSample>& out) override {
    // Per-zone deltas (each with its own wrap) accumulate into one monotonic total.
    for (Zone& z : zones_) {
      const uint64_t now = readSysfsCounter(z.energyPath);
      total_ += counterDelta(z.last, now, z.maxRange);
      z.last = now;
    }
    if (auto s = counter_.update(clock_.nowNs(), total_)) {
      ++status_.samples;
      out.push_back(*s);
    }
  }

 private:
  const Clock& clock_;
  MeterInfo info_;
  MeterStatus status_;
  std::vector<Zone> zones_;
  EnergyCounter counter_;
  uint64_t total_ = 0;
};

}  // namespace

void RaplSettings::read(ConfigReader& r, bool) {
  r.string("root", root);
  r.strings("zones", zones);
  r.integer("poll_interval_ms", pollIntervalMs, 1, 10000);
}

nlohmann::json RaplSettings::toJson() const {
  return {{"root", root}, {"zones", zones}, {"poll_interval_ms", pollIntervalMs}};
}

std::unique_ptr<Meter> openRapl(const RaplSettings& settings, const MeterHostSettings&, const Clock& clock) {
  return std::make_unique<RaplMeter>(settings, clock);
}

}  // namespace sb::power
