// The energy ledger: exact integrals (constant power, ramps, steps), emission only after a later sample,
// gaps and meter loss never guessed, idle baseline, run totals.

#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "power/energy_ledger.h"

using namespace sb::power;

namespace {

constexpr int64_t kS = 1'000'000'000;  // ns per second

PowerSample at(int64_t tNs, double watts, bool gapBefore = false) {
  PowerSample s;
  s.tNs = tNs;
  s.watts = watts;
  s.gapBefore = gapBefore;
  return s;
}

bool relativelyEqual(double a, double b, double tolerance = 1e-9) {
  return std::abs(a - b) <= tolerance * std::max(std::abs(a), std::abs(b));
}

}  // namespace

TEST_CASE("ledger: constant power over known intervals gives P*dt to 1e-9 relative", "[power][ledger]") {
  for (SampleKind kind : {SampleKind::instantaneous, SampleKind::intervalAverage}) {
    LedgerOptions o;
    o.kind = kind;
    EnergyLedger ledger(o);
    const double watts = 4.2;
    const int64_t t0 = 123'456 * kS;  // a monotonic clock some 34 hours after boot
    for (int i = 0; i <= 10; ++i) ledger.addSample(at(t0 + i * kS, watts));
    std::mt19937_64 rng(7);
    std::vector<FrameInterval> frames;
    int64_t t = t0 + kS / 3;
    for (uint64_t f = 0; t < t0 + 9 * kS; ++f) {
      const int64_t duration = 1'000'000 + static_cast<int64_t>(rng() % 900'000'000);  // 1 ms .. 0.9 s
      frames.push_back({f, t, t + duration});
      ledger.addFrame(frames.back());
      t += duration + static_cast<int64_t>(rng() % 5'000'000);
    }
    const auto out = ledger.takeReady();
    REQUIRE(out.size() == frames.size());
    for (size_t i = 0; i < out.size(); ++i) {
      INFO("frame " << i);
      REQUIRE(out[i].known);
      CHECK(out[i].frame == frames[i].frame);
      const double expected = watts * static_cast<double>(frames[i].endNs - frames[i].startNs) * 1e-9;
      CHECK(relativelyEqual(out[i].joules, expected));
      CHECK(relativelyEqual(out[i].meanWatts, watts));
    }
  }
}

TEST_CASE("ledger: a linear ramp sampled irregularly integrates to the analytic value", "[power][ledger]") {
  // P(t) = 2 + 0.75 t (t in s): linear interpolation reproduces it exactly wherever it is sampled.
  EnergyLedger ledger;
  auto power = [](double t) { return 2.0 + 0.75 * t; };
  auto energy = [](double a, double b) { return 2.0 * (b - a) + 0.375 * (b * b - a * a); };
  const std::vector<double> times{0.0, 0.13, 0.9, 1.0, 2.71, 3.3, 5.05, 6.0};
  for (double t : times) ledger.addSample(at(static_cast<int64_t>(std::llround(t * 1e9)), power(t)));
  const std::vector<std::pair<double, double>> frames{{0.05, 0.1}, {0.1, 1.5}, {0.2, 5.9}, {2.71, 3.3}, {4.0, 6.0}};
  for (size_t i = 0; i < frames.size(); ++i)
    ledger.addFrame({i, std::llround(frames[i].first * 1e9), std::llround(frames[i].second * 1e9)});
  const auto out = ledger.takeReady();
  REQUIRE(out.size() == frames.size());
  for (size_t i = 0; i < out.size(); ++i) {
    INFO("frame " << i);
    REQUIRE(out[i].known);
    CHECK(relativelyEqual(out[i].joules, energy(frames[i].first, frames[i].second)));
  }
}

TEST_CASE("ledger: piecewise-linear load (ramps between samples) and steps of a counter meter", "[power][ledger]") {
  SECTION("trapezoid wave sampled at its corners: linear interpolation is exact") {
    // 3 W, ramp to 7 W over 0.2 s, hold 0.3 s, ramp down over 0.1 s, hold 3 W 0.4 s; repeated.
    EnergyLedger ledger;
    std::vector<std::pair<int64_t, double>> corners;
    for (int period = 0; period < 5; ++period) {
      const int64_t base = period * kS;
      corners.push_back({base, 3.0});
      corners.push_back({base + 200'000'000, 7.0});
      corners.push_back({base + 500'000'000, 7.0});
      corners.push_back({base + 600'000'000, 3.0});
    }
    corners.push_back({5 * kS, 3.0});
    for (const auto& c : corners) ledger.addSample(at(c.first, c.second));
    // Analytic energy per period: ramp up 0.2*(3+7)/2 = 1.0, hold 0.3*7 = 2.1, ramp down 0.1*5 = 0.5,
    // hold 0.4*3 = 1.2 -> 4.8 J. Over [0.1, 0.55]: 0.1*(5+7)/2 + 0.3*7 + 0.05*(7+5)/2 = 0.6 + 2.1 + 0.3 = 3.0 J.
    ledger.addFrame({0, 0, 5 * kS});
    ledger.addFrame({1, kS + 100'000'000, kS + 550'000'000});
    const auto out = ledger.takeReady();
    REQUIRE(out.size() == 2);
    CHECK(relativelyEqual(out[0].joules, 5 * 4.8));
    CHECK(relativelyEqual(out[1].joules, 3.0));
  }
  SECTION("interval averages held piecewise constant reproduce the counter's energy") {
    LedgerOptions o;
    o.kind = SampleKind::intervalAverage;
    EnergyLedger ledger(o);
    // A counter read every 0.1 s; the load steps 10 W -> 25 W at t = 0.3 s and -> 5 W at t = 0.7 s.
    ledger.addSample(at(0, 0.0));
    for (int i = 1; i <= 10; ++i) ledger.addSample(at(i * kS / 10, i <= 3 ? 10.0 : (i <= 7 ? 25.0 : 5.0)));
    ledger.addFrame({0, 0, kS});                                   // 0.3*10 + 0.4*25 + 0.3*5 = 14.5 J
    ledger.addFrame({1, 250'000'000, 750'000'000});                // 0.05*10 + 0.4*25 + 0.05*5 = 10.75 J
    const auto out = ledger.takeReady();
    REQUIRE(out.size() == 2);
    CHECK(relativelyEqual(out[0].joules, 14.5));
    CHECK(relativelyEqual(out[1].joules, 10.75));
  }
}

TEST_CASE("ledger: a frame is emitted only once a sample at or after its end exists", "[power][ledger]") {
  EnergyLedger ledger;
  ledger.addSample(at(0, 2.0));
  ledger.addSample(at(kS, 2.0));
  ledger.addFrame({0, kS / 2, 2 * kS + kS / 2});
  ledger.addFrame({1, 2 * kS + kS / 2, 2 * kS + 600'000'000});
  ledger.addSample(at(2 * kS, 4.0));
  CHECK(ledger.takeReady().empty());
  CHECK(ledger.pendingFrames() == 2);
  ledger.addSample(at(2 * kS + 600'000'000, 4.0));  // exactly frame 1's end: both resolve, in order
  const auto out = ledger.takeReady();
  REQUIRE(out.size() == 2);
  CHECK(out[0].frame == 0);
  CHECK(out[1].frame == 1);
  // [0.5, 1]: 2 W; [1, 2]: ramp 2 -> 4 W = 3 J; [2, 2.5]: 4 W -> 1 + 3 + 2 = 6 J
  CHECK(relativelyEqual(out[0].joules, 6.0));
  CHECK(relativelyEqual(out[1].joules, 0.4));
}

TEST_CASE("ledger: gaps make frames unknown, never guessed", "[power][ledger]") {
  LedgerOptions o;
  o.maxSampleSpacingNs = 3 * kS;
  EnergyLedger ledger(o);
  ledger.addFrame({0, -kS, kS / 2});                   // starts before the first sample
  ledger.addSample(at(0, 5.0));
  ledger.addSample(at(kS, 5.0));
  ledger.addSample(at(2 * kS, 5.0, /*gapBefore=*/true));  // the meter was away between 1 s and 2 s
  ledger.addSample(at(3 * kS, 5.0));
  ledger.addSample(at(10 * kS, 5.0));                  // 7 s without samples: more than the 3 s limit
  ledger.addSample(at(11 * kS, 5.0));
  ledger.addFrame({1, kS / 4, 3 * kS / 4});            // known
  ledger.addFrame({2, 3 * kS / 4, 5 * kS / 4});        // reaches into the gap
  ledger.addFrame({3, 2 * kS, 3 * kS});                // known
  ledger.addFrame({4, 3 * kS + 1, 3 * kS + 2});        // inside the too-long stretch
  ledger.addFrame({5, 10 * kS, 11 * kS});              // known again
  const auto out = ledger.takeReady();
  REQUIRE(out.size() == 6);
  CHECK_FALSE(out[0].known);
  CHECK(out[0].unknownReason.find("before the first power sample") != std::string::npos);
  CHECK(std::isnan(out[0].joules));
  CHECK(out[1].known);
  CHECK_FALSE(out[2].known);
  CHECK(out[2].unknownReason == "meter gap");
  CHECK(out[3].known);
  CHECK_FALSE(out[4].known);
  CHECK(out[5].known);
  CHECK(relativelyEqual(out[5].joules, 5.0));
  const EnergyTotals& t = ledger.totals();
  CHECK(t.knownFrames == 3);
  CHECK(t.unknownFrames == 3);
  CHECK(relativelyEqual(t.joules, 2.5 + 5.0 + 5.0));
}

TEST_CASE("ledger: a lost meter resolves waiting frames as unknown at once", "[power][ledger]") {
  EnergyLedger ledger;
  ledger.addSample(at(0, 1.0));
  ledger.addSample(at(kS, 1.0));
  ledger.addFrame({0, kS / 2, 3 * kS / 2});
  CHECK(ledger.takeReady().empty());
  ledger.meterLost("smartpower2: end of file: unplugged");
  auto out = ledger.takeReady();
  REQUIRE(out.size() == 1);
  CHECK_FALSE(out[0].known);
  CHECK(out[0].unknownReason == "smartpower2: end of file: unplugged");
  ledger.addFrame({1, 2 * kS, 3 * kS});  // while lost: unknown immediately
  out = ledger.takeReady();
  REQUIRE(out.size() == 1);
  CHECK_FALSE(out[0].known);
  // Back: the stretch across the loss stays unknown, later frames are known.
  ledger.addSample(at(4 * kS, 2.0));
  ledger.addSample(at(5 * kS, 2.0));
  CHECK_FALSE(ledger.lost());
  ledger.addFrame({2, 3 * kS + kS / 2, 4 * kS + kS / 2});
  ledger.addFrame({3, 4 * kS + kS / 2, 5 * kS});
  out = ledger.takeReady();
  REQUIRE(out.size() == 2);
  CHECK_FALSE(out[0].known);
  CHECK(out[1].known);
  CHECK(relativelyEqual(out[1].joules, 1.0));
}

TEST_CASE("ledger: idle baseline, totals over frames and over the whole span", "[power][ledger]") {
  LedgerOptions o;
  o.idleWatts = 3.0;
  EnergyLedger ledger(o);
  for (int i = 0; i <= 4; ++i) ledger.addSample(at(i * kS, 5.0));
  // Two frames of 1 s with 0.5 s between them.
  ledger.addFrame({0, kS / 2, 3 * kS / 2});
  ledger.addFrame({1, 2 * kS, 3 * kS});
  const auto out = ledger.takeReady();
  REQUIRE(out.size() == 2);
  CHECK(relativelyEqual(out[0].joulesAboveIdle, 2.0));
  const EnergyTotals& t = ledger.totals();
  CHECK(relativelyEqual(t.joules, 10.0));
  CHECK(relativelyEqual(t.joulesAboveIdle, 4.0));
  CHECK(relativelyEqual(t.meanWatts(), 5.0));
  CHECK(relativelyEqual(t.joulesPerFrame(), 5.0));
  CHECK(relativelyEqual(t.seconds, 2.0));
  CHECK(relativelyEqual(t.spanSeconds, 2.5));
  CHECK(relativelyEqual(t.spanKnownSeconds, 2.5));
  CHECK(relativelyEqual(t.spanJoules, 12.5));
  CHECK(t.idleWatts == 3.0);
}

TEST_CASE("ledger: out-of-order samples are dropped; finish() marks what never got a sample", "[power][ledger]") {
  EnergyLedger ledger;
  CHECK(ledger.addSample(at(kS, 1.0)));
  CHECK_FALSE(ledger.addSample(at(kS, 9.0)));
  CHECK_FALSE(ledger.addSample(at(0, 9.0)));
  CHECK(ledger.droppedSamples() == 2);
  ledger.addSample(at(2 * kS, 1.0));
  ledger.addFrame({0, kS, 2 * kS});
  ledger.addFrame({1, 2 * kS, 3 * kS});
  const auto out = ledger.finish("stopped");
  REQUIRE(out.size() == 2);
  CHECK(out[0].known);
  CHECK(relativelyEqual(out[0].joules, 1.0));
  CHECK_FALSE(out[1].known);
  CHECK(out[1].unknownReason == "stopped");
  CHECK(ledger.pendingFrames() == 0);
}

TEST_CASE("ledger: old samples are pruned but a late frame within the retention still resolves", "[power][ledger]") {
  LedgerOptions o;
  o.retainNs = 5 * kS;
  EnergyLedger ledger(o);
  for (int i = 0; i <= 100; ++i) ledger.addSample(at(i * kS / 10, 2.0));  // 10 s at 10 Hz
  ledger.addFrame({0, 6 * kS, 7 * kS});   // 3 s late: still held
  ledger.addFrame({1, 1 * kS, 2 * kS});   // 8 s late: its samples are gone
  const auto out = ledger.takeReady();
  REQUIRE(out.size() == 2);
  CHECK(out[0].known);
  CHECK(relativelyEqual(out[0].joules, 2.0));
  CHECK_FALSE(out[1].known);
  CHECK(out[1].unknownReason.find("discarded") != std::string::npos);
}

TEST_CASE("ledger: keeping every sample works at any time value (no overflow in the retention)", "[power][ledger]") {
  LedgerOptions o;
  o.retainNs = INT64_MAX;  // offline accounting keeps the whole trace
  EnergyLedger ledger(o);
  for (int i = -10; i <= -5; ++i) ledger.addSample(at(i * kS, 3.0));
  ledger.addFrame({0, -10 * kS, -6 * kS});
  const auto out = ledger.takeReady();
  REQUIRE(out.size() == 1);
  REQUIRE(out[0].known);
  CHECK(relativelyEqual(out[0].joules, 12.0));
}
