// `slambooster energy` end to end: a recorded trace and frames.jsonl give the library's numbers; bad input
// exits 1 with a message naming the file.

#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "power/offline_accounting.h"
#include "power/power_trace.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

using namespace sb::power;

namespace {

sb::test::CommandResult runEnergy(const std::string& args) {
  return sb::test::runCommand(std::string(SB_SLAMBOOSTER_BIN) + " energy " + args);
}

struct Run {
  std::string dir, trace, frames;
};

// 1 Hz SmartPower2-like trace with an unplugged stretch, and 10 s of frames at 10 fps.
Run recordRun(const std::string& name) {
  Run r;
  r.dir = sb::test::scratchDir(name);
  r.trace = r.dir + "/power.csv";
  r.frames = r.dir + "/frames.jsonl";
  MeterInfo m;
  m.name = "smartpower2";
  m.device = "/dev/ttyUSB0";
  m.nominalPeriodNs = 1'000'000'000;
  PowerTraceWriter writer(r.trace, m);
  const int64_t t0 = 20'000'000'000;
  for (int i = 0; i <= 12; ++i) {
    if (i == 6) writer.lost(t0 + 5'500'000'000);  // unplugged between 5 s and 7 s
    if (i == 6) continue;
    PowerSample s;
    s.tNs = t0 + int64_t(i) * 1'000'000'000;
    s.watts = 4.0 + 0.1 * i;
    s.volts = 5.1;
    s.gapBefore = i == 7;
    writer.sample(s);
  }
  std::ofstream frames(r.frames);
  for (int f = 0; f < 100; ++f) {
    const int64_t start = t0 + 500'000'000 + int64_t(f) * 100'000'000;
    frames << nlohmann::json{{"frame", f}, {"timestamp", 1.0 + f / 10.0}, {"tracked", true},
                             {"t_start_mono_ns", start}, {"t_end_mono_ns", start + 80'000'000}}.dump()
           << "\n";
  }
  return r;
}

}  // namespace

TEST_CASE("slambooster energy --json agrees with the library", "[power][cli]") {
  const Run r = recordRun("energy_cli_json");
  const std::string perFrame = r.dir + "/energy.jsonl";
  const auto result = runEnergy("--json --idle-watts 3.5 --trace " + r.trace + " --frames " + r.frames + " --out " + perFrame);
  INFO(result.output);
  REQUIRE(result.exitCode == 0);
  const auto j = nlohmann::json::parse(result.output);
  OfflineOptions o;
  o.idleWatts = 3.5;
  const OfflineResult lib = accountOffline(readPowerTrace(r.trace), readFrameIntervals(r.frames), o);
  CHECK(j.at("class") == "ENERGY_SUMMARY");
  CHECK(j.at("meter") == "smartpower2");
  CHECK(j.at("frames") == 100);
  CHECK(j.at("known_frames").get<uint64_t>() == lib.totals.knownFrames);
  CHECK(lib.totals.unknownFrames == 20);  // frames overlapping (5 s, 7 s]
  CHECK(j.at("unknown_frames") == 20);
  CHECK(j.at("joules").get<double>() == Approx(lib.totals.joules).epsilon(1e-12));
  CHECK(j.at("joules_above_idle").get<double>() == Approx(lib.totals.joulesAboveIdle).epsilon(1e-12));
  CHECK(j.at("span_joules").get<double>() == Approx(lib.totals.spanJoules).epsilon(1e-12));
  CHECK(j.at("idle_watts") == 3.5);
  CHECK(j.at("unknown_reasons").size() == 1);

  std::ifstream in(perFrame);
  std::string line;
  size_t count = 0, unknown = 0;
  while (std::getline(in, line)) {
    const auto e = nlohmann::json::parse(line);
    CHECK(e.at("frame") == count);
    if (!e.at("known").get<bool>()) {
      ++unknown;
      CHECK(e.at("joules").is_null());
      CHECK(e.contains("unknown_reason"));
    } else {
      CHECK(e.at("joules").get<double>() == Approx(lib.frames[count].joules).epsilon(1e-12));
    }
    ++count;
  }
  CHECK(count == 100);
  CHECK(unknown == 20);
}

TEST_CASE("slambooster energy prints a table; bad input exits 1 naming the file", "[power][cli]") {
  const Run r = recordRun("energy_cli_table");
  auto result = runEnergy("--trace " + r.trace + " --frames " + r.frames);
  INFO(result.output);
  CHECK(result.exitCode == 0);
  CHECK(result.output.find("frames 100: energy known for 80, unknown for 20") != std::string::npos);
  CHECK(result.output.find("J/frame") != std::string::npos);

  std::ofstream(r.dir + "/old_frames.jsonl") << "{\"frame\": 0, \"timestamp\": 1.0}\n";
  result = runEnergy("--trace " + r.trace + " --frames " + r.dir + "/old_frames.jsonl");
  CHECK(result.exitCode == 1);
  CHECK(result.output.find("old_frames.jsonl' line 1") != std::string::npos);
  CHECK(result.output.find("t_start_mono_ns") != std::string::npos);

  result = runEnergy("--trace " + r.dir + "/absent.csv --frames " + r.frames);
  CHECK(result.exitCode == 1);
  CHECK(result.output.find("absent.csv") != std::string::npos);
  result = runEnergy("--trace " + r.trace);
  CHECK(result.exitCode == 2);
}
