// SmartPower3: line format and checksums (golden lines recorded from devices), channel selection, and the
// driver against a pseudo-terminal simulator at 921600 baud (banner, partial first line, corrupted lines,
// batches spaced by the device clock, unplug and replug).

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "power/clock.h"
#include "power/smartpower3.h"
#include "tests/power/pty_simulator.h"
#include "tests/support/test_data.h"

using namespace sb::power;

namespace {

// Lines as the device prints them. Golden values from the test suite of connorimes/osp3 (test/test_osp3_unit.c:
// one line from the Hardkernel wiki, three recorded from a device running firmware v2.2).
const char* const kGolden[] = {
    "0000815169,15296,0036,00550,0,00000,0000,00000,0,00,00000,0000,00000,0,00,14,12",
    "0343732187,15321,0072,01103,0,00000,0000,00000,0,00,00000,0000,00000,0,00,1c,12",
    "0343732197,15332,0084,01287,0,00000,0000,00000,0,00,00000,0000,00000,0,00,09,17",
    "0343732207,15328,0055,00843,0,00000,0000,00000,0,00,00000,0000,00000,0,00,11,19",
};

// Builds a line with the firmware's field widths; the checksums are computed here independently of the
// parser (and checked against the golden lines below before being trusted).
std::string makeLine(unsigned long ms, int inMv, int inMa, int inMw, int mv1, int ma1, int mw1, int mv2, int ma2,
                     int mw2, bool corruptChecksum = false) {
  char body[96];
  std::snprintf(body, sizeof body, "%010lu,%05d,%04d,%05d,%1d,%05d,%04d,%05d,%1d,%02x,%05d,%04d,%05d,%1d,%02x,", ms,
                inMv, inMa, inMw, 0, mv1, ma1, mw1, 1, 0, mv2, ma2, mw2, 1, 0x10);
  unsigned sum = 0, x = 0;
  for (const char* p = body; *p; ++p) {
    sum += static_cast<unsigned char>(*p);
    x ^= static_cast<unsigned char>(*p);
  }
  char tail[16];
  std::snprintf(tail, sizeof tail, "%02x,%02x", (256 - (sum & 0xff)) & 0xff, (x ^ (corruptChecksum ? 1u : 0u)) & 0xff);
  return std::string(body) + tail;
}

SmartPower3Settings sp3Config(const std::string& device, const std::string& channel = "1") {
  SmartPower3Settings c;
  c.device = device;
  c.channel = channel;
  return c;
}

}  // namespace

TEST_CASE("smartpower3 lines: golden device lines pass their checksums, altered ones do not", "[power][smartpower3]") {
  LineReading r;
  for (const char* line : kGolden) {
    INFO(line);
    CHECK(std::string(line).size() + 2 == 81);  // 81 bytes with "\r\n"
    REQUIRE(parseSmartPower3Line(line, SmartPower3Channel::input, r) == LineResult::sample);
  }
  parseSmartPower3Line(kGolden[0], SmartPower3Channel::input, r);
  CHECK(r.deviceMs == 815169);
  CHECK(r.volts == Approx(15.296));
  CHECK(r.amps == Approx(0.036));
  CHECK(r.watts == Approx(0.550));
  // The test's line builder agrees with the device on the golden line's fields.
  CHECK(makeLine(815169, 15296, 36, 550, 0, 0, 0, 0, 0, 0).substr(0, 30) == std::string(kGolden[0]).substr(0, 30));

  std::string bad2s = kGolden[0], badXor = kGolden[0], badBody = kGolden[1];
  bad2s[75] = '5';                // 2's complement checksum 14 -> 15
  badXor[78] = '3';               // xor checksum 12 -> 13
  badBody[12] = '4';              // input mV 15321 -> 14321: both checksums now disagree
  CHECK(parseSmartPower3Line(bad2s, SmartPower3Channel::input, r) == LineResult::checksumError);
  CHECK(parseSmartPower3Line(badXor, SmartPower3Channel::input, r) == LineResult::checksumError);
  CHECK(parseSmartPower3Line(badBody, SmartPower3Channel::input, r) == LineResult::checksumError);
  for (const char* junk : {"", "SmartPower3 v2.2", "0343732187,15321,0072", "a,b,c,d,e,f,g,h,i,j,k,l,m,n,o,p,q",
                           "0343732187,15321,0072,01103,0,00000,0000,00000,0,00,00000,0000,00000,0,00,1c,12,00",
                           "0343732187,15321,0072,01103,0,00000,0000,00000,0,00,00000,0000,00000,0,00,1c"}) {
    INFO(junk);
    CHECK(parseSmartPower3Line(junk, SmartPower3Channel::input, r) == LineResult::skipped);
  }
}

TEST_CASE("smartpower3 channel selection", "[power][smartpower3]") {
  const std::string line = makeLine(1234, 15000, 500, 7500, 5100, 800, 4080, 12000, 250, 3000);
  LineReading r;
  REQUIRE(parseSmartPower3Line(line, SmartPower3Channel::output1, r) == LineResult::sample);
  CHECK(r.watts == Approx(4.080));
  CHECK(r.volts == Approx(5.100));
  CHECK(r.amps == Approx(0.800));
  REQUIRE(parseSmartPower3Line(line, SmartPower3Channel::output2, r) == LineResult::sample);
  CHECK(r.watts == Approx(3.000));
  CHECK(r.volts == Approx(12.0));
  REQUIRE(parseSmartPower3Line(line, SmartPower3Channel::both, r) == LineResult::sample);
  CHECK(r.watts == Approx(7.080));
  CHECK(std::isnan(r.volts));
  REQUIRE(parseSmartPower3Line(line, SmartPower3Channel::input, r) == LineResult::sample);
  CHECK(r.watts == Approx(7.5));
  CHECK(r.deviceMs == 1234);
  CHECK(parseSmartPower3Line(makeLine(1234, 15000, 500, 7500, 5100, 800, 4080, 12000, 250, 3000, true),
                             SmartPower3Channel::output1, r) == LineResult::checksumError);
}

TEST_CASE("smartpower3 driver on a pty: checksums, device-clock spacing, unplug and replug", "[power][smartpower3]") {
  const std::string dir = sb::test::scratchDir("power_sp3");
  sb::test::PtySimulator sim(dir + "/ttyUSB0");
  ManualClock clock(50'000'000'000);
  MeterHostSettings host;
  host.reopenMinMs = 100;
  auto meter = openSmartPower3(sp3Config(sim.path(), "2"), host, clock);
  CHECK(meter->info().nominalPeriodNs == 10'000'000);

  std::vector<PowerSample> samples;
  const std::string first = makeLine(1000, 15000, 500, 7500, 5100, 800, 4080, 12000, 250, 3000);
  sim.write(first.substr(40) + "\r\n");                       // the tail of a line in flight at open
  sim.write("\r\nSmartPower3 booting...\r\nWiFi off\r\n");     // banner
  sim.write(makeLine(1005, 15000, 500, 7500, 5100, 800, 4080, 12000, 250, 3000, true) + "\r\n");  // corrupted
  sim.write(makeLine(1010, 15000, 500, 7500, 5100, 800, 4080, 12000, 300, 3600) + "\r\n");
  sim.write(makeLine(1020, 15000, 500, 7500, 5100, 800, 4080, 12000, 400, 4800) + "\r\n");
  sim.write(makeLine(1030, 15000, 500, 7500, 5100, 800, 4080, 12000, 500, 6000) + "\r\n");
  sb::test::settle(*meter);
  meter->poll(samples);
  // Lines read in one batch are spaced back from the read time by the device's millisecond clock.
  REQUIRE(samples.size() == 3);
  CHECK(samples[0].watts == Approx(3.6));
  CHECK(samples[1].watts == Approx(4.8));
  CHECK(samples[2].watts == Approx(6.0));
  CHECK(samples[2].tNs == 50'000'000'000);
  CHECK(samples[1].tNs == 50'000'000'000 - 10'000'000);
  CHECK(samples[0].tNs == 50'000'000'000 - 20'000'000);
  MeterStatus st = meter->status();
  CHECK(st.checksumErrors == 1);
  CHECK(st.rejected == 4);  // partial first line, empty line, 2 banner lines

  // Unplug, replug at the same path: the gap is reported and the first new sample is marked.
  clock.advance(5'000'000);
  sim.unplug();
  sb::test::pollFor(*meter, samples);
  CHECK_FALSE(meter->status().connected);
  sim.replug();
  clock.advance(100'000'000);
  meter->poll(samples);
  REQUIRE(meter->status().connected);
  sim.write(makeLine(9000, 15000, 500, 7500, 5100, 800, 4080, 12000, 500, 6000).substr(3) + "\r\n");
  sim.write(makeLine(9010, 15000, 500, 7500, 5100, 800, 4080, 12000, 100, 1200) + "\r\n");
  REQUIRE(sb::test::pollUntil(*meter, samples, 4));
  CHECK(samples[3].watts == Approx(1.2));
  CHECK(samples[3].gapBefore);
  CHECK(samples[3].tNs == 50'105'000'000);
  CHECK(meter->status().reconnects == 1);
}
