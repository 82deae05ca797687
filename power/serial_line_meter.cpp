#include "power/serial_line_meter.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "core/error.h"
#include "power/serial_port.h"

namespace sb::power {

SerialLineMeter::SerialLineMeter(SerialLineOptions options, LineParser parser, const Clock& clock)
    : options_(std::move(options)), parser_(std::move(parser)), clock_(clock) {
  info_.name = options_.name;
  info_.device = options_.device;
  info_.kind = SampleKind::instantaneous;
  info_.nominalPeriodNs = options_.nominalPeriodNs;
  SerialOpenResult r = openSerialPort(options_.device, options_.baud);
  if (!r.fd.valid()) throw Error(options_.name + " meter: " + r.error);
  fd_ = std::move(r.fd);
  splitter_.reset(true);
  status_.sinceNs = clock_.nowNs();
  backoffNs_ = options_.reopenMinNs;
}

MeterStatus SerialLineMeter::status() const {
  MeterStatus s = status_;
  s.rejected += splitter_.droppedLines();
  return s;
}

int64_t SerialLineMeter::pollPeriodNs() const {
  if (fd_.valid()) return std::min<int64_t>(options_.nominalPeriodNs, 100'000'000);
  return std::max<int64_t>(1'000'000, nextRetryNs_ - clock_.nowNs());
}

void SerialLineMeter::lose(const std::string& why) {
  fd_.reset();
  const int64_t now = clock_.nowNs();
  status_.connected = false;
  status_.sinceNs = now;
  status_.message = why;
  backoffNs_ = options_.reopenMinNs;
  nextRetryNs_ = now + backoffNs_;
  gapPending_ = true;
  spdlog::warn("{} meter '{}': device lost ({}); reopening with backoff from {} ms", options_.name,
               options_.device, why, backoffNs_ / 1'000'000);
}

void SerialLineMeter::tryReopen() {
  const int64_t now = clock_.nowNs();
  if (now < nextRetryNs_) return;
  SerialOpenResult r = openSerialPort(options_.device, options_.baud);
  if (!r.fd.valid()) {
    backoffNs_ = std::min(options_.reopenMaxNs, backoffNs_ * 2);
    nextRetryNs_ = now + backoffNs_;
    status_.message = r.error;
    return;
  }
  fd_ = std::move(r.fd);
  splitter_.reset(true);
  spdlog::info("{} meter '{}': device back after {:.1f} s; energy in the gap is unknown", options_.name,
               options_.device, nsToSeconds(now - status_.sinceNs));
  status_.connected = true;
  status_.sinceNs = now;
  status_.message.clear();
  ++status_.reconnects;
}

void SerialLineMeter::poll(std::vector<PowerSample>& out) {
  if (!fd_.valid()) tryReopen();
  if (!fd_.valid()) return;
  std::vector<std::string> lines;
  char buffer[4096];
  for (;;) {
    const ssize_t n = ::read(fd_.get(), buffer, sizeof buffer);
    if (n > 0) {
      splitter_.push(buffer, static_cast<size_t>(n), lines);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
    const std::string why = n == 0 ? "end of file: unplugged" : std::string("read: ") + std::strerror(errno);
    emit(lines, out);  // complete lines read before the loss are still good
    lose(why);
    return;
  }
  emit(lines, out);
}

void SerialLineMeter::emit(const std::vector<std::string>& lines, std::vector<PowerSample>& out) {
  std::vector<LineReading> readings;
  for (const std::string& line : lines) {
    LineReading reading;
    switch (parser_(line, reading)) {
      case LineResult::sample: readings.push_back(reading); break;
      case LineResult::checksumError: ++status_.checksumErrors; break;
      case LineResult::skipped: ++status_.rejected; break;
    }
  }
  if (readings.empty()) return;
  // All lines of one read share the read time. The device clock (when there is one) spaces them back in
  // time from the newest; without it only the newest line can be timestamped honestly.
  const int64_t readNs = clock_.nowNs();
  const bool deviceClock = std::all_of(readings.begin(), readings.end(), [](const LineReading& r) {
    return r.deviceMs >= 0;
  }) && std::is_sorted(readings.begin(), readings.end(), [](const LineReading& a, const LineReading& b) {
    return a.deviceMs < b.deviceMs;
  });
  const int64_t newestMs = readings.back().deviceMs;
  for (size_t i = 0; i < readings.size(); ++i) {
    const bool newest = i + 1 == readings.size();
    if (!newest && !deviceClock) {
      ++status_.rejected;
      continue;
    }
    const LineReading& r = readings[i];
    const int64_t t = newest ? readNs : readNs - (newestMs - r.deviceMs) * 1'000'000;
    if (t <= lastSampleNs_) {
      ++status_.rejected;
      continue;
    }
    PowerSample s;
    s.tNs = t;
    s.watts = r.watts;
    s.volts = r.volts;
    s.amps = r.amps;
    s.gapBefore = gapPending_;
    gapPending_ = false;
    lastSampleNs_ = t;
    ++status_.samples;
    out.push_back(s);
  }
}

}  // namespace sb::power
