#include "drivers/device_clock.h"

#include <time.h>

#include <algorithm>

namespace sb {

namespace {
constexpr double kMinStep = 1e-6;  // seconds: consecutive mapped times differ by at least this
}

double DeviceClock::monotonicNow() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double DeviceClock::map(uint64_t deviceMicros, double hostSeconds) {
  const double device = 1e-6 * static_cast<double>(deviceMicros);
  const double observed = hostSeconds - device;  // true offset + transfer delay
  if (!offset_ || device <= lastDevice_) {
    offset_ = observed;
  } else {
    const double allowance = driftPpm_ * 1e-6 * std::max(0.0, hostSeconds - lastHost_);
    offset_ = std::min(*offset_ + allowance, observed);
  }
  lastDevice_ = device;
  lastHost_ = hostSeconds;
  double mapped = device + *offset_;
  if (lastMapped_ && mapped < *lastMapped_ + kMinStep) mapped = *lastMapped_ + kMinStep;
  lastMapped_ = mapped;
  return mapped;
}

}  // namespace sb
