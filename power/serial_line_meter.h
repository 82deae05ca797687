#pragma once
// The host side shared by the line-oriented USB serial meters (the SmartPower serial models): opens the tty,
// splits lines, timestamps them when read, and survives unplugging (reopens with exponential backoff and
// marks the first sample after the gap). The meter-specific part is only a line parser.

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "power/clock.h"
#include "power/line_splitter.h"
#include "power/meter.h"
#include "core/unique_fd.h"

namespace sb::power {

// A measurement parsed from one line.
struct LineReading {
  double watts = 0.0;
  double volts = NAN;
  double amps = NAN;
  int64_t deviceMs = -1;  // the device's own millisecond clock when the line carries one, else -1
};

enum class LineResult {
  sample,         // `reading` holds a measurement
  skipped,        // not a measurement line (banner, debug output, garbage)
  checksumError,  // shaped like a measurement but its checksum does not match
};

using LineParser = std::function<LineResult(std::string_view line, LineReading& reading)>;

struct SerialLineOptions {
  std::string name;               // registry name, for info() and messages
  std::string device;             // tty path (opened again by path after unplugging: symlinks are followed)
  int baud = 115200;
  int64_t nominalPeriodNs = 1'000'000'000;
  int64_t reopenMinNs = 250'000'000;
  int64_t reopenMaxNs = 8'000'000'000;
};

class SerialLineMeter final : public Meter {
 public:
  // Opens the device; throws sb::Error (naming the path and the fix) when it cannot be opened at start.
  SerialLineMeter(SerialLineOptions options, LineParser parser, const Clock& clock);

  const MeterInfo& info() const override { return info_; }
  void poll(std::vector<PowerSample>& out) override;
  MeterStatus status() const override;
  int waitFd() const override { return fd_.get(); }
  int64_t pollPeriodNs() const override;

 private:
  void lose(const std::string& why);
  void tryReopen();
  void emit(const std::vector<std::string>& lines, std::vector<PowerSample>& out);

  SerialLineOptions options_;
  LineParser parser_;
  const Clock& clock_;
  MeterInfo info_;
  MeterStatus status_;
  UniqueFd fd_;
  LineSplitter splitter_;
  int64_t nextRetryNs_ = 0;
  int64_t backoffNs_ = 0;
  int64_t lastSampleNs_ = 0;
  bool gapPending_ = false;  // the next sample follows a loss
};

}  // namespace sb::power
