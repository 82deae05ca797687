// SmartPower2: the line parser, and the driver against a pseudo-terminal simulator (banner, partial first
// line, garbage, split and over-long lines, unplug mid-run and replug at the same path).

#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "core/error.h"
#include "power/clock.h"
#include "power/smartpower2.h"
#include "tests/power/pty_simulator.h"
#include "tests/support/test_data.h"

using namespace sb::power;

TEST_CASE("smartpower2 parser accepts V,A,W,Wh lines and skips everything else", "[power][smartpower2]") {
  LineReading r;
  REQUIRE(parseSmartPower2Line("5.102,0.340,1.735,0.000", r) == LineResult::sample);
  CHECK(r.volts == Approx(5.102));
  CHECK(r.amps == Approx(0.340));
  CHECK(r.watts == Approx(1.735));
  CHECK(r.deviceMs == -1);
  CHECK(parseSmartPower2Line("5.102,0.340,1.735,12.500", r) == LineResult::sample);  // Wh ignored
  for (const char* line : {"", "SmartPower2 v1.3", "5.102,0.340,1.735", "5.102,0.340,1.735,0.000,1",
                           "5.102,,1.735,0.000", "-5.102,0.340,1.735,0.000", "5.1.2,0.340,1.735,0.000",
                           "5.102,0.340,1.735,0.000 ", "ets Jan  8 2013,rst cause:2, boot mode:(3,6)",
                           "99.000,0.340,1.735,0.000", "5.102,0.340,1e3,0.000", ".5,0.340,1.735,0.000"}) {
    INFO(line);
    CHECK(parseSmartPower2Line(line, r) == LineResult::skipped);
  }
}

namespace {

SmartPower2Settings sp2Config(const std::string& device) {
  SmartPower2Settings c;
  c.device = device;
  return c;
}

}  // namespace

TEST_CASE("smartpower2 driver on a pty: banner, partial first line, garbage, split lines", "[power][smartpower2]") {
  const std::string dir = sb::test::scratchDir("power_sp2_lines");
  sb::test::PtySimulator sim(dir + "/ttyUSB0");
  ManualClock clock(5'000'000'000);
  auto meter = openSmartPower2(sp2Config(sim.path()), MeterHostSettings{250, 8000}, clock);
  CHECK(meter->info().name == "smartpower2");
  CHECK(meter->info().kind == SampleKind::instantaneous);
  REQUIRE(meter->waitFd() >= 0);

  std::vector<PowerSample> samples;
  // The open happened mid-line: "23,0.456,2.335,0.000" parses but is the tail of "5.123,..."; it is dropped.
  sim.write("23,0.456,2.335,0.000\r\n");
  sim.write("\r\nets Jan  8 2013,rst cause:2, boot mode:(3,6)\r\nSmartPower2 ready\r\n");
  const char garbage[] = "\x00\xff\xfe garbage\r\n";
  sim.write(std::string(garbage, sizeof garbage - 1));
  sim.write("5.102,0.340,1.735,0.000\r\n");
  REQUIRE(sb::test::pollUntil(*meter, samples, 1));
  REQUIRE(samples.size() == 1);
  CHECK(samples[0].watts == Approx(1.735));
  CHECK(samples[0].volts == Approx(5.102));
  CHECK(samples[0].amps == Approx(0.340));
  CHECK(samples[0].tNs == 5'000'000'000);  // timestamped by the clock when read
  CHECK_FALSE(samples[0].gapBefore);
  CHECK(meter->status().rejected == 5);  // partial first line, empty line, 2 banner lines, garbage

  // A line that arrives in pieces is joined; a line longer than any meter line is dropped up to its newline.
  clock.advance(1'000'000'000);
  sim.write("5.0");
  sb::test::pollFor(*meter, samples);
  CHECK(samples.size() == 1);
  sim.write("98,0.400,2.");
  sb::test::pollFor(*meter, samples);
  sim.write("039,0.000\r\n" + std::string(400, '7') + "\r\n");
  REQUIRE(sb::test::pollUntil(*meter, samples, 2));
  CHECK(samples[1].watts == Approx(2.039));
  CHECK(samples[1].tNs == 6'000'000'000);
  CHECK(meter->status().rejected == 6);  // + the over-long line

  // Two lines read in one go carry no device clock: only the newest can be timestamped honestly.
  clock.advance(1'000'000'000);
  sim.write("5.097,0.410,2.090,0.000\r\n5.096,0.420,2.140,0.000\r\n");
  sb::test::settle(*meter);
  meter->poll(samples);
  REQUIRE(samples.size() == 3);
  CHECK(samples[2].watts == Approx(2.140));
  CHECK(samples[2].tNs == 7'000'000'000);
  CHECK(meter->status().rejected == 7);
  CHECK(meter->status().samples == 3);
  CHECK(meter->status().connected);
}

TEST_CASE("smartpower2 driver survives unplugging: reports the gap, reopens with backoff", "[power][smartpower2]") {
  const std::string dir = sb::test::scratchDir("power_sp2_unplug");
  sb::test::PtySimulator sim(dir + "/ttyUSB0");
  ManualClock clock(10'000'000'000);
  auto meter = openSmartPower2(sp2Config(sim.path()), MeterHostSettings{250, 8000}, clock);
  std::vector<PowerSample> samples;
  sim.write("0.000,0.000,0.000,0.000\r\n5.100,0.500,2.550,0.000\r\n");
  REQUIRE(sb::test::pollUntil(*meter, samples, 1));

  // Unplug mid-run: the driver sees end of file and reports the loss at that time.
  clock.advance(1'000'000'000);
  sim.unplug();
  sb::test::pollFor(*meter, samples);
  MeterStatus st = meter->status();
  CHECK_FALSE(st.connected);
  CHECK(st.sinceNs == 11'000'000'000);
  CHECK(st.message.find("unplugged") != std::string::npos);
  CHECK(meter->waitFd() == -1);
  CHECK(meter->pollPeriodNs() == 250'000'000);

  // Before the backoff has passed nothing is tried; after it the reopen fails (the tty is gone) and the
  // backoff doubles.
  clock.advance(200'000'000);
  meter->poll(samples);
  CHECK(meter->status().message.find("unplugged") != std::string::npos);
  clock.advance(100'000'000);
  meter->poll(samples);
  st = meter->status();
  CHECK_FALSE(st.connected);
  CHECK(st.message.find("No such file") != std::string::npos);
  CHECK(st.message.find("plugged in") != std::string::npos);
  CHECK(meter->pollPeriodNs() == 500'000'000);

  // Replugged at the same path: reopened once the doubled backoff has passed.
  sim.replug();
  clock.advance(400'000'000);
  meter->poll(samples);
  CHECK_FALSE(meter->status().connected);
  clock.advance(100'000'000);
  meter->poll(samples);
  st = meter->status();
  REQUIRE(st.connected);
  CHECK(st.reconnects == 1);
  CHECK(samples.size() == 1);

  // The first sample after the gap says so; the ones after it do not.
  sim.write("5.1");  // the new connection also starts mid-line
  sim.write("00,0.500,2.550,0.000\r\n5.090,0.600,3.054,0.000\r\n");
  REQUIRE(sb::test::pollUntil(*meter, samples, 2));
  CHECK(samples[1].watts == Approx(3.054));
  CHECK(samples[1].gapBefore);
  clock.advance(1'000'000'000);
  sim.write("5.080,0.700,3.556,0.000\r\n");
  REQUIRE(sb::test::pollUntil(*meter, samples, 3));
  CHECK_FALSE(samples[2].gapBefore);
  CHECK(samples[2].tNs > samples[1].tNs);
}

TEST_CASE("smartpower2 driver: a device that is not there at start is a clear error", "[power][smartpower2]") {
  const std::string dir = sb::test::scratchDir("power_sp2_absent");
  try {
    openSmartPower2(sp2Config(dir + "/ttyUSB9"), {}, monotonicClock());
    FAIL("expected an error");
  } catch (const sb::Error& e) {
    const std::string what = e.what();
    CHECK(what.find("smartpower2") != std::string::npos);
    CHECK(what.find(dir + "/ttyUSB9") != std::string::npos);
    CHECK(what.find("plugged in") != std::string::npos);
  }
}
