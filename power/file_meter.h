#pragma once
// Replays a recorded power trace (power_trace.h) as a live meter: the trace's times are shifted so that its
// first event happens when the meter is opened, and poll() returns the events whose time has come. Lost
// events and the end of the trace show as a disconnected meter. For re-accounting a finished run offline use
// `slambooster energy` instead, which keeps the recorded times.

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/config_reader.h"
#include "power/clock.h"
#include "power/meter.h"
#include "power/power_trace.h"

namespace sb::power {

// The "file" section of the power config (config/README.md).
struct FileMeterSettings {
  std::string path;                     // a power trace CSV (power_trace.h); required when selected

  void read(ConfigReader& r, bool selected);  // key: path (required when the meter is selected)
  nlohmann::json toJson() const;
};

class FileMeter final : public Meter {
 public:
  FileMeter(PowerTrace trace, std::string path, const Clock& clock);

  const MeterInfo& info() const override { return info_; }
  void poll(std::vector<PowerSample>& out) override;
  MeterStatus status() const override { return status_; }
  int64_t pollPeriodNs() const override;

 private:
  PowerTrace trace_;
  const Clock& clock_;
  MeterInfo info_;
  MeterStatus status_;
  int64_t offsetNs_ = 0;  // add to trace times to get clock times
  size_t next_ = 0;
};

std::unique_ptr<Meter> openFileMeter(const FileMeterSettings& settings, const MeterHostSettings& host, const Clock& clock);

}  // namespace sb::power
