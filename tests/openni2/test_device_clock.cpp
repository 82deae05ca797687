// DeviceClock: device timestamps mapped onto CLOCK_MONOTONIC.

#include <catch2/catch.hpp>

#include "drivers/device_clock.h"

using sb::DeviceClock;

TEST_CASE("device clock: the offset is the least transfer delay seen", "[openni2][clock]") {
  DeviceClock c(0.0);
  // Device stamps every 33 ms from 5 s; host arrival = 100 s + device time + a delay of 8, 3, 12, 5 ms.
  const double delays[] = {0.008, 0.003, 0.012, 0.005};
  double previous = 0.0;
  for (int i = 0; i < 4; ++i) {
    const uint64_t device = 5000000 + 33000 * i;
    const double host = 100.0 + 1e-6 * device + delays[i];
    const double t = c.map(device, host);
    CHECK(t <= host);  // never later than the arrival
    if (i > 0) CHECK(t > previous);
    previous = t;
  }
  REQUIRE(c.offset());
  CHECK(*c.offset() == Approx(100.003).margin(1e-9));  // the smallest delay (3 ms) wins
  CHECK(c.map(5000000 + 33000 * 4, 100.0 + 5.132 + 0.020) == Approx(100.0 + 5.132 + 0.003).margin(1e-9));
}

TEST_CASE("device clock: a slower device clock is followed within the drift allowance", "[openni2][clock]") {
  // The device clock runs 100 ppm slow: the observed offset grows by 100 us per second; frames arrive 2 ms
  // after they were stamped.
  auto run = [](double allowancePpm) {
    DeviceClock c(allowancePpm);
    double t = 0.0;
    for (int i = 0; i <= 600; ++i) {
      const double host = 50.0 + 0.1 * i;
      const uint64_t device = static_cast<uint64_t>(1e6 * (0.1 * i) * (1.0 - 100e-6));
      t = c.map(device, host + 0.002);
    }
    return t;
  };
  // After 60 s: with a 200 ppm allowance the mapping still follows the arrivals; without, it lags 6 ms.
  CHECK(run(200.0) == Approx(110.002).margin(2e-5));
  CHECK(run(0.0) == Approx(110.002 - 0.006).margin(2e-5));
}

TEST_CASE("device clock: a device restart resets the offset; mapped times keep increasing", "[openni2][clock]") {
  DeviceClock c;
  const double a = c.map(9000000, 10.0);
  const double b = c.map(9033000, 10.033);
  // The device restarted: its clock is back near zero, while host time goes on.
  const double d = c.map(1000, 10.050);
  const double e = c.map(34000, 10.083);
  CHECK(a < b);
  CHECK(b < d);
  CHECK(d < e);
  CHECK(d == Approx(10.050).margin(1e-9));
  CHECK(e == Approx(10.083).margin(1e-9));
  // reset(): the next frame starts a new estimate, still after the last mapped time.
  c.reset();
  CHECK_FALSE(c.offset());
  const double f = c.map(0, 10.0);  // a host time in the past cannot go backwards
  CHECK(f > e);
}

TEST_CASE("device clock: monotonicNow is CLOCK_MONOTONIC seconds", "[openni2][clock]") {
  const double t0 = DeviceClock::monotonicNow();
  const double t1 = DeviceClock::monotonicNow();
  CHECK(t1 >= t0);
  CHECK(t0 > 0.0);
}
