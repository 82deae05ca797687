// The sampler driving a real serial driver on a pty with the real clock: the thread wakes on the tty's
// descriptor, timestamps lines when they arrive, and frames between two lines get their joules.

#include <catch2/catch.hpp>
#include <chrono>
#include <thread>

#include "power/clock.h"
#include "power/power_sampler.h"
#include "power/smartpower2.h"
#include "tests/power/pty_simulator.h"
#include "tests/support/test_data.h"

using namespace sb::power;

TEST_CASE("sampler + smartpower2 on a pty: frames between lines get joules", "[power][sampler][smartpower2]") {
  const std::string dir = sb::test::scratchDir("power_sampler_serial");
  sb::test::PtySimulator sim(dir + "/ttyUSB0");
  PowerConfig c;
  c.meter = "smartpower2";
  SmartPower2Settings settings;
  settings.device = sim.path();
  PowerSampler sampler(openSmartPower2(settings, c.host(), monotonicClock()), samplerOptions(c, dir + "/power.csv"));
  sampler.start();
  auto waitSamples = [&](uint64_t n) {
    for (int i = 0; i < 2000 && sampler.meterStatus().samples < n; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    return sampler.meterStatus().samples >= n;
  };
  sim.write("tail of a line\r\n5.000,1.000,5.000,0.000\r\n");
  REQUIRE(waitSamples(1));
  const int64_t start = monotonicClock().nowNs();
  std::this_thread::sleep_for(std::chrono::milliseconds(5));
  const int64_t end = monotonicClock().nowNs();
  sampler.addFrame({0, start, end});
  std::this_thread::sleep_for(std::chrono::milliseconds(2));
  CHECK(sampler.takeResults().empty());  // no sample after the frame's end yet
  sim.write("5.000,1.000,5.000,0.000\r\n");
  REQUIRE(waitSamples(2));
  std::vector<FrameEnergy> results;
  for (int i = 0; i < 2000 && results.empty(); ++i) {
    results = sampler.takeResults();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  REQUIRE(results.size() == 1);
  REQUIRE(results[0].known);
  CHECK(results[0].joules == Approx(5.0 * static_cast<double>(end - start) * 1e-9).epsilon(1e-9));
  sampler.stop();
  CHECK(sampler.totals().knownFrames == 1);
}
