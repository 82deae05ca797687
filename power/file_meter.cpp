#include "power/file_meter.h"

#include <algorithm>

#include "core/error.h"

namespace sb::power {

FileMeter::FileMeter(PowerTrace trace, std::string path, const Clock& clock)
    : trace_(std::move(trace)), clock_(clock) {
  info_ = trace_.meter;
  info_.name = "file";
  info_.device = std::move(path);
  if (trace_.events.empty()) throw Error("file meter: power trace '" + info_.device + "' holds no samples");
  offsetNs_ = clock_.nowNs() - trace_.events.front().sample.tNs;
  status_.sinceNs = clock_.nowNs();
}

int64_t FileMeter::pollPeriodNs() const {
  if (next_ >= trace_.events.size()) return 1'000'000'000;
  const int64_t due = trace_.events[next_].sample.tNs + offsetNs_ - clock_.nowNs();
  return std::clamp<int64_t>(due, 1'000'000, 100'000'000);
}

void FileMeter::poll(std::vector<PowerSample>& out) {
  const int64_t now = clock_.nowNs();
  while (next_ < trace_.events.size() && trace_.events[next_].sample.tNs + offsetNs_ <= now) {
    const TraceEvent& e = trace_.events[next_++];
    const int64_t t = e.sample.tNs + offsetNs_;
    if (e.lost) {
      if (status_.connected) {
        status_.connected = false;
        status_.sinceNs = t;
        status_.message = "the recorded meter was lost here";
      }
      continue;
    }
    if (!status_.connected) {
      status_.connected = true;
      status_.sinceNs = t;
      status_.message.clear();
      ++status_.reconnects;
    }
    PowerSample s = e.sample;
    s.tNs = t;
    ++status_.samples;
    out.push_back(s);
  }
  if (next_ >= trace_.events.size() && status_.connected) {
    status_.connected = false;
    status_.sinceNs = now;
    status_.message = "end of the power trace '" + info_.device + "'";
  }
}

void FileMeterSettings::read(ConfigReader& r, bool selected) {
  r.string("path", path);
  if (selected && path.empty())
    r.fail("path", "a power trace written by a profiling run (meter \"file\" needs it)");
}

nlohmann::json FileMeterSettings::toJson() const { return {{"path", path}}; }

std::unique_ptr<Meter> openFileMeter(const FileMeterSettings& settings, const MeterHostSettings&, const Clock& clock) {
  if (settings.path.empty()) throw Error("file meter: set 'file.path' to a power trace");
  return std::make_unique<FileMeter>(readPowerTrace(settings.path), settings.path, clock);
}

}  // namespace sb::power
