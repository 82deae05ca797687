#include "power/clock.h"

#include <time.h>

namespace sb::power {

int64_t MonotonicClock::nowNs() const {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

const Clock& monotonicClock() {
  static const MonotonicClock clock;
  return clock;
}

}  // namespace sb::power
