// The raw power trace: exact round trip, malformed files named with their line, replay as the "file" meter,
// and offline re-accounting of a run (trace + frames.jsonl) that matches the live ledger.

#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "power/clock.h"
#include "power/file_meter.h"
#include "power/power_config.h"
#include "power/offline_accounting.h"
#include "power/power_trace.h"
#include "tests/support/test_data.h"

using namespace sb::power;

namespace {

MeterInfo testMeter() {
  MeterInfo m;
  m.name = "smartpower3";
  m.device = "/dev/serial/by-id/usb-Silicon_Labs_CP2104, ttyUSB0";  // a comma and spaces survive
  m.kind = SampleKind::instantaneous;
  m.nominalPeriodNs = 10'000'000;
  return m;
}

std::vector<TraceEvent> writeExample(const std::string& path) {
  std::vector<TraceEvent> events;
  auto sample = [&](int64_t t, double w, double v, double a, bool gap) {
    TraceEvent e;
    e.sample.tNs = t;
    e.sample.watts = w;
    e.sample.volts = v;
    e.sample.amps = a;
    e.sample.gapBefore = gap;
    events.push_back(e);
  };
  sample(1'000'000'000, 4.321, 5.102, 0.847, false);
  sample(1'010'000'000, 0.1 + 0.2, NAN, NAN, false);  // a value with no short exact decimal
  sample(1'020'000'000, 1.0 / 3.0, 5.0, NAN, false);
  TraceEvent lost;
  lost.lost = true;
  lost.sample.tNs = 1'500'000'000;
  events.push_back(lost);
  sample(2'000'000'000, 6.5, 5.0, 1.3, true);
  sample(2'010'000'000, 6.25, 5.0, 1.25, false);
  PowerTraceWriter writer(path, testMeter());
  for (const TraceEvent& e : events) {
    if (e.lost) writer.lost(e.sample.tNs);
    else writer.sample(e.sample);
  }
  return events;
}

void expectSame(const PowerSample& a, const PowerSample& b) {
  CHECK(a.tNs == b.tNs);
  CHECK(a.watts == b.watts);  // bit-exact
  CHECK((std::isnan(a.volts) ? std::isnan(b.volts) : a.volts == b.volts));
  CHECK((std::isnan(a.amps) ? std::isnan(b.amps) : a.amps == b.amps));
  CHECK(a.gapBefore == b.gapBefore);
}

}  // namespace

TEST_CASE("power trace: written and read back exactly", "[power][trace]") {
  const std::string path = sb::test::scratchDir("power_trace_roundtrip") + "/power.csv";
  const auto events = writeExample(path);
  const PowerTrace trace = readPowerTrace(path);
  CHECK(trace.meter.name == "smartpower3");
  CHECK(trace.meter.device == testMeter().device);
  CHECK(trace.meter.kind == SampleKind::instantaneous);
  CHECK(trace.meter.nominalPeriodNs == 10'000'000);
  REQUIRE(trace.events.size() == events.size());
  for (size_t i = 0; i < events.size(); ++i) {
    INFO("event " << i);
    CHECK(trace.events[i].lost == events[i].lost);
    if (!events[i].lost) expectSame(trace.events[i].sample, events[i].sample);
    else CHECK(trace.events[i].sample.tNs == events[i].sample.tNs);
  }
}

TEST_CASE("power trace: malformed files are refused with file and line", "[power][trace]") {
  const std::string dir = sb::test::scratchDir("power_trace_bad");
  const std::string header =
      "# {\"format\":\"slambooster-power-trace\",\"version\":1,\"meter\":\"rapl\",\"device\":\"x\","
      "\"kind\":\"interval_average\",\"nominal_period_ns\":10000000,\"clock\":\"CLOCK_MONOTONIC\"}\n"
      "t_ns,watts,volts,amps,event\n";
  auto check = [&](const std::string& name, const std::string& text, const std::string& expected) {
    const std::string path = dir + "/" + name;
    std::ofstream(path) << text;
    INFO(name);
    CHECK_THROWS_WITH(readPowerTrace(path), Catch::Contains(path) && Catch::Contains(expected));
  };
  check("no_header.csv", "t_ns,watts,volts,amps,event\n1,2,,,\n", "line 1");
  check("bad_kind.csv", "# {\"format\":\"slambooster-power-trace\",\"version\":1,\"meter\":\"x\",\"device\":\"x\","
                        "\"kind\":\"sometimes\",\"nominal_period_ns\":1}\nt_ns,watts,volts,amps,event\n", "sometimes");
  check("fields.csv", header + "100,1.5,,\n", "line 3: expected 5 fields");
  check("watts.csv", header + "100,1.5,,,\n200,lots,,,\n", "line 4: bad watts 'lots'");
  check("backwards.csv", header + "200,1.5,,,\n100,1.5,,,\n", "line 4: time goes backwards");
  check("event.csv", header + "100,1.5,,,boom\n", "unknown event 'boom'");
  CHECK_THROWS_WITH(readPowerTrace(dir + "/absent.csv"), Catch::Contains("cannot open power trace"));
  std::ofstream(dir + "/ok.csv") << header << "100,1.5,,,\n";
  CHECK(readPowerTrace(dir + "/ok.csv").meter.kind == SampleKind::intervalAverage);
}

TEST_CASE("file meter replays a trace at the pace of the clock, with its gaps", "[power][trace]") {
  const std::string path = sb::test::scratchDir("power_trace_replay") + "/power.csv";
  writeExample(path);
  PowerConfig c;
  c.meter = "file";
  c.meters["file"]["path"] = path;
  ManualClock clock(50'000'000'000);
  auto meter = openMeter(c, clock);
  CHECK(meter->info().name == "file");
  CHECK(meter->info().kind == SampleKind::instantaneous);
  std::vector<PowerSample> samples;
  meter->poll(samples);
  REQUIRE(samples.size() == 1);  // the first event happens at the open
  CHECK(samples[0].tNs == 50'000'000'000);
  clock.advance(15'000'000);
  meter->poll(samples);
  CHECK(samples.size() == 2);
  clock.advance(500'000'000);  // past the recorded loss
  meter->poll(samples);
  CHECK(samples.size() == 3);
  CHECK_FALSE(meter->status().connected);
  clock.advance(490'000'000);  // the first sample after the loss is due, the next one 10 ms later
  meter->poll(samples);
  REQUIRE(samples.size() == 4);
  CHECK(samples[3].gapBefore);
  CHECK(samples[3].tNs == 51'000'000'000);
  CHECK(meter->status().connected);
  clock.advance(1'000'000'000);
  meter->poll(samples);
  CHECK(samples.size() == 5);
  CHECK_FALSE(meter->status().connected);
  CHECK(meter->status().message.find("end of the power trace") != std::string::npos);
}

TEST_CASE("offline accounting: frames.jsonl + trace give the live ledger's numbers", "[power][trace]") {
  const std::string dir = sb::test::scratchDir("power_offline");
  // A 100 Hz instantaneous trace of a 2 Hz sine-like load, and 50 frames of 20 ms every 25 ms.
  MeterInfo m = testMeter();
  LedgerOptions live;
  live.kind = m.kind;
  live.maxSampleSpacingNs = 1'500'000'000;
  live.idleWatts = 1.5;
  EnergyLedger ledger(live);
  {
    PowerTraceWriter writer(dir + "/power.csv", m);
    for (int i = 0; i <= 200; ++i) {
      PowerSample s;
      s.tNs = 7'000'000'000 + i * 10'000'000;
      s.watts = 4.0 + std::sin(i * 0.1256);
      writer.sample(s);
      ledger.addSample(s);
    }
  }
  std::ofstream frames(dir + "/frames.jsonl");
  std::vector<FrameEnergy> expected;
  for (uint64_t f = 0; f < 50; ++f) {
    const FrameInterval fi{f, 7'005'000'000 + int64_t(f) * 25'000'000, 7'025'000'000 + int64_t(f) * 25'000'000};
    frames << nlohmann::json{{"frame", f}, {"timestamp", 1.5 + f}, {kFrameStartKey, fi.startNs}, {kFrameEndKey, fi.endNs}}.dump()
           << "\n";
    ledger.addFrame(fi);
  }
  frames.close();
  expected = ledger.finish();

  OfflineOptions o;
  o.idleWatts = 1.5;
  const OfflineResult r = accountOffline(readPowerTrace(dir + "/power.csv"), readFrameIntervals(dir + "/frames.jsonl"), o);
  REQUIRE(r.frames.size() == expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    CHECK(r.frames[i].known == expected[i].known);
    CHECK(r.frames[i].joules == expected[i].joules);  // bit-exact: same samples, same arithmetic
    CHECK(r.frames[i].joulesAboveIdle == expected[i].joulesAboveIdle);
  }
  CHECK(r.totals.joules == ledger.totals().joules);
  CHECK(r.totals.spanJoules == ledger.totals().spanJoules);
}

TEST_CASE("offline accounting: a frame log without monotonic times is refused", "[power][trace]") {
  const std::string dir = sb::test::scratchDir("power_offline_bad");
  std::ofstream(dir + "/frames.jsonl") << "{\"frame\": 0, \"timestamp\": 1.0}\n";
  CHECK_THROWS_WITH(readFrameIntervals(dir + "/frames.jsonl"),
                    Catch::Contains("line 1") && Catch::Contains("t_start_mono_ns"));
  std::ofstream(dir + "/frames2.jsonl") << "{\"frame\": 0, \"t_start_mono_ns\": 5, \"t_end_mono_ns\": 4}\n";
  CHECK_THROWS_WITH(readFrameIntervals(dir + "/frames2.jsonl"), Catch::Contains("before"));
  std::ofstream(dir + "/frames3.jsonl") << "{\"frame\": 0,\n";
  CHECK_THROWS_WITH(readFrameIntervals(dir + "/frames3.jsonl"), Catch::Contains("not valid JSON"));
}
