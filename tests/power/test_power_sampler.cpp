// The sampling thread: per-frame results (queue or callback) in order, the raw trace that re-accounts to the
// same numbers, stop() draining, meter loss and silence, the "none" meter, and the idle baseline.

#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <fstream>
#include <mutex>
#include <thread>

#include "power/power_config.h"
#include "power/offline_accounting.h"
#include "power/power_sampler.h"
#include "tests/power/scripted_meter.h"
#include "tests/support/test_data.h"

using namespace sb::power;
using sb::test::ScriptedMeter;

namespace {

constexpr int64_t kMs = 1'000'000;
constexpr int64_t kT0 = 100'000 * kMs;  // 100 s

// Collects results until `count` have arrived (real-time bound: a failing test must not hang).
std::vector<FrameEnergy> collect(PowerSampler& sampler, size_t count, int timeoutMs = 5000) {
  std::vector<FrameEnergy> all;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeoutMs);
  while (all.size() < count && std::chrono::steady_clock::now() < deadline) {
    auto more = sampler.takeResults();
    all.insert(all.end(), more.begin(), more.end());
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return all;
}

double ramp(int64_t t) { return 3.0 + 2.0 * static_cast<double>(t - kT0) * 1e-9; }  // 3 W + 2 W/s

}  // namespace

TEST_CASE("sampler: per-frame joules in order, and a trace that re-accounts to the same numbers", "[power][sampler]") {
  const std::string dir = sb::test::scratchDir("power_sampler_trace");
  ManualClock clock(kT0);
  auto owned = std::make_unique<ScriptedMeter>();
  ScriptedMeter& meter = *owned;
  SamplerOptions o;
  o.tracePath = dir + "/power.csv";
  PowerSampler sampler(std::move(owned), o, clock);
  sampler.setIdleWatts(1.0);
  sampler.start();
  std::vector<FrameInterval> frames;
  for (uint64_t k = 0; k < 20; ++k) {
    frames.push_back({k, kT0 + 5 * kMs + int64_t(k) * 20 * kMs, kT0 + 20 * kMs + int64_t(k) * 20 * kMs});
    sampler.addFrame(frames.back());
  }
  for (int i = 0; i <= 50; ++i) meter.push(kT0 + i * 10 * kMs, ramp(kT0 + i * 10 * kMs));
  const auto results = collect(sampler, frames.size());
  REQUIRE(results.size() == frames.size());
  for (size_t k = 0; k < results.size(); ++k) {
    INFO("frame " << k);
    CHECK(results[k].frame == k);
    REQUIRE(results[k].known);
    const double a = static_cast<double>(frames[k].startNs - kT0) * 1e-9, b = static_cast<double>(frames[k].endNs - kT0) * 1e-9;
    const double exact = 3.0 * (b - a) + (b * b - a * a);
    CHECK(results[k].joules == Approx(exact).epsilon(1e-9));
    CHECK(results[k].joulesAboveIdle == Approx(exact - (b - a)).epsilon(1e-9));
  }
  CHECK(sampler.stop().empty());
  const EnergyTotals totals = sampler.totals();
  CHECK(totals.knownFrames == 20);
  CHECK(totals.idleWatts == 1.0);

  // Re-accounting the recorded trace gives bit-identical per-frame joules.
  OfflineOptions offline;
  offline.idleWatts = 1.0;
  const OfflineResult r = accountOffline(readPowerTrace(o.tracePath), frames, offline);
  REQUIRE(r.frames.size() == results.size());
  for (size_t k = 0; k < results.size(); ++k) CHECK(r.frames[k].joules == results[k].joules);
  CHECK(r.totals.joules == Approx(totals.joules).epsilon(1e-12));
  CHECK(r.totals.spanJoules == Approx(totals.spanJoules).epsilon(1e-12));
}

TEST_CASE("sampler: callback on the sampler thread; stop() drains, then marks what got no sample", "[power][sampler]") {
  ManualClock clock(kT0);
  auto owned = std::make_unique<ScriptedMeter>();
  ScriptedMeter& meter = *owned;
  SamplerOptions o;
  o.drainTimeoutNs = 30 * kMs;
  PowerSampler sampler(std::move(owned), o, clock);
  std::mutex mutex;
  std::vector<FrameEnergy> seen;
  std::thread::id callbackThread;
  sampler.setCallback([&](const FrameEnergy& e) {
    std::lock_guard<std::mutex> lock(mutex);
    seen.push_back(e);
    callbackThread = std::this_thread::get_id();
  });
  sampler.start();
  meter.push(kT0, 2.0);
  meter.push(kT0 + 100 * kMs, 2.0);
  sampler.addFrame({0, kT0 + 10 * kMs, kT0 + 60 * kMs});
  sampler.addFrame({1, kT0 + 60 * kMs, kT0 + 150 * kMs});  // ends after the last sample so far
  sampler.addFrame({2, kT0 + 150 * kMs, kT0 + 180 * kMs});
  for (int i = 0; i < 5000; ++i) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (!seen.empty()) break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  meter.push(kT0 + 160 * kMs, 2.0);  // frame 1 resolves in the drain; frame 2 never gets a later sample
  CHECK(sampler.stop().empty());     // everything went to the callback
  REQUIRE(seen.size() == 3);
  CHECK(callbackThread != std::this_thread::get_id());
  CHECK(seen[0].known);
  CHECK(seen[0].joules == Approx(0.1).epsilon(1e-12));
  CHECK(seen[1].known);
  CHECK(seen[1].joules == Approx(0.18).epsilon(1e-12));
  CHECK_FALSE(seen[2].known);
  CHECK(seen[2].unknownReason.find("before the sampler stopped") != std::string::npos);
  CHECK(sampler.stop().empty());  // twice is fine
}

TEST_CASE("sampler: a lost meter and a silent meter make frames unknown and are recorded", "[power][sampler]") {
  const std::string dir = sb::test::scratchDir("power_sampler_lost");
  ManualClock clock(kT0);
  auto owned = std::make_unique<ScriptedMeter>(SampleKind::instantaneous, 1000 * kMs);
  ScriptedMeter& meter = *owned;
  SamplerOptions o;
  o.tracePath = dir + "/power.csv";
  o.drainTimeoutNs = 0;
  PowerSampler sampler(std::move(owned), o, clock);
  CHECK(sampler.maxGapNs() == 3000 * kMs);  // automatic: 3 periods of a 1 Hz meter
  sampler.start();
  meter.push(kT0, 5.0);
  meter.push(kT0 + 1000 * kMs, 5.0);
  sampler.addFrame({0, kT0 + 100 * kMs, kT0 + 900 * kMs});
  sampler.addFrame({1, kT0 + 900 * kMs, kT0 + 1500 * kMs});
  auto results = collect(sampler, 1);
  REQUIRE(results.size() == 1);
  CHECK(results[0].known);
  // Unplugged: the waiting frame resolves as unknown with the driver's reason.
  clock.set(kT0 + 1200 * kMs);
  meter.setConnected(false, "end of file: unplugged");
  results = collect(sampler, 1);
  REQUIRE(results.size() == 1);
  CHECK_FALSE(results[0].known);
  CHECK(results[0].unknownReason == "end of file: unplugged");
  CHECK_FALSE(sampler.meterStatus().connected);
  // Back, then silent for longer than the gap limit: the watchdog declares the loss.
  meter.setConnected(true);
  meter.push(kT0 + 5000 * kMs, 5.0, true);
  meter.push(kT0 + 6000 * kMs, 5.0);
  // Frames happen after the samples that precede them have been read (a frame added while the meter is
  // still lost is unknown).
  for (int i = 0; i < 5000 && sampler.meterStatus().samples < 4; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  sampler.addFrame({2, kT0 + 5500 * kMs, kT0 + 5600 * kMs});
  sampler.addFrame({3, kT0 + 5600 * kMs, kT0 + 7000 * kMs});
  results = collect(sampler, 1);
  REQUIRE(results.size() == 1);
  CHECK(results[0].known);
  clock.set(kT0 + 9500 * kMs);
  results = collect(sampler, 1);
  REQUIRE(results.size() == 1);
  CHECK_FALSE(results[0].known);
  CHECK(results[0].unknownReason.find("no power samples for more than 3000 ms") != std::string::npos);
  sampler.stop();
  const PowerTrace trace = readPowerTrace(o.tracePath);
  size_t lost = 0;
  for (const TraceEvent& e : trace.events) lost += e.lost;
  CHECK(lost == 2);
  CHECK(trace.events.size() == 6);
}

TEST_CASE("sampler: a meter that throws is a gap, not a crash", "[power][sampler]") {
  ManualClock clock(kT0);
  auto owned = std::make_unique<ScriptedMeter>();
  ScriptedMeter& meter = *owned;
  PowerSampler sampler(std::move(owned), {}, clock);
  sampler.start();
  meter.push(kT0, 2.0);
  meter.push(kT0 + 10 * kMs, 2.0);
  for (int i = 0; i < 5000 && sampler.meterStatus().samples < 2; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  meter.throwOnPoll("cannot read '/sys/class/powercap/intel-rapl:0/energy_uj': No such device");
  sampler.addFrame({0, kT0 + 5 * kMs, kT0 + 20 * kMs});
  auto results = collect(sampler, 1);
  REQUIRE(results.size() == 1);
  CHECK_FALSE(results[0].known);
  CHECK(results[0].unknownReason.find("No such device") != std::string::npos);
  CHECK_FALSE(sampler.meterStatus().connected);
  meter.throwOnPoll("");
  meter.push(kT0 + 30 * kMs, 2.0, true);
  meter.push(kT0 + 40 * kMs, 2.0);
  for (int i = 0; i < 5000 && sampler.meterStatus().samples < 4; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  CHECK(sampler.meterStatus().connected);
  sampler.addFrame({1, kT0 + 30 * kMs, kT0 + 40 * kMs});
  results = collect(sampler, 1);
  REQUIRE(results.size() == 1);
  CHECK(results[0].known);
  CHECK(results[0].joules == Approx(0.02).epsilon(1e-12));
  sampler.stop();
}

TEST_CASE("sampler: with the none meter every frame is unknown at once", "[power][sampler]") {
  PowerConfig c;
  PowerSampler sampler(openMeter(c), samplerOptions(c));
  sampler.start();
  sampler.addFrame({0, 1, 2});
  sampler.addFrame({1, 2, 3});
  auto results = collect(sampler, 2);
  REQUIRE(results.size() == 2);
  for (const FrameEnergy& e : results) {
    CHECK_FALSE(e.known);
    CHECK(e.unknownReason.find("no power meter configured") != std::string::npos);
  }
  CHECK(sampler.stop().empty());
  CHECK(sampler.totals().unknownFrames == 2);
}

TEST_CASE("sampler: idle baseline measured before the run", "[power][sampler]") {
  ManualClock clock(kT0);
  auto owned = std::make_unique<ScriptedMeter>();
  ScriptedMeter& meter = *owned;
  meter.autoSample(&clock, 50 * kMs, 2.5);  // every poll: 50 ms pass and a 2.5 W sample arrives
  PowerSampler sampler(std::move(owned), {}, clock);
  CHECK(sampler.measureIdle(2.0) == Approx(2.5).epsilon(1e-12));
  CHECK(meter.polls() >= 40);
  CHECK(sampler.totals().idleWatts == Approx(2.5));

  ManualClock still(kT0);
  auto none = std::make_unique<ScriptedMeter>();
  none->autoSample(&still, 100 * kMs, 0.0);
  PowerSampler empty(std::move(none), {}, still);
  CHECK_THROWS_WITH(empty.measureIdle(0.05), Catch::Contains("fewer than two samples"));
}
