// How much per-frame accuracy a 1 Hz meter (SmartPower2) loses against a 200 Hz one (SmartPower3 at 5 ms),
// on a synthetic load: 60 s of frames at ~30 fps (25-45 ms each), each a busy phase at a power that changes
// with the knob level every ~4 s, then an idle phase at 3 W. Two meter models: point samples of the
// instantaneous power (linear interpolation) and averages over the meter's interval (held constant).
// Prints the errors (quoted in power/README.md); the checks guard them against regressions.

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "power/energy_ledger.h"

using namespace sb::power;

namespace {

constexpr int64_t kMs = 1'000'000;

// The true load: piecewise constant, breakpoints in ns.
struct Load {
  std::vector<int64_t> t;     // t[i] .. t[i+1] holds p[i]
  std::vector<double> p;
  double power(int64_t x) const {
    const auto it = std::upper_bound(t.begin(), t.end(), x);
    return p[static_cast<size_t>(std::max<ptrdiff_t>(0, it - t.begin() - 1))];
  }
  double energy(int64_t a, int64_t b) const {  // exact
    double e = 0.0;
    for (size_t i = 0; i + 1 < t.size(); ++i) {
      const int64_t lo = std::max(a, t[i]), hi = std::min(b, t[i + 1]);
      if (hi > lo) e += p[i] * static_cast<double>(hi - lo) * 1e-9;
    }
    return e;
  }
};

struct Workload {
  Load load;
  std::vector<FrameInterval> frames;
  std::vector<double> truth;  // J per frame
};

Workload makeWorkload() {
  Workload w;
  std::mt19937 rng(2024);
  std::uniform_int_distribution<int64_t> durationNs(25 * kMs, 45 * kMs);  // not on a lattice of the meter's ticks
  std::uniform_real_distribution<double> busyFraction(0.5, 0.9);
  const double levels[] = {6.5, 5.5, 4.8, 4.2};  // W while busy: more approximation, less power
  const double idle = 3.0;
  int64_t t = 0, nextLevelChange = 0;
  double busy = levels[0];
  for (uint64_t f = 0; t < 60'000 * kMs; ++f) {
    if (t >= nextLevelChange) {
      busy = levels[rng() % 4];
      nextLevelChange = t + (3000 + static_cast<int64_t>(rng() % 2000)) * kMs;
    }
    const int64_t duration = durationNs(rng);
    const int64_t busyEnd = t + static_cast<int64_t>(std::llround(busyFraction(rng) * static_cast<double>(duration)));
    w.load.t.push_back(t);
    w.load.p.push_back(busy);
    w.load.t.push_back(busyEnd);
    w.load.p.push_back(idle);
    w.frames.push_back({f, t, t + duration});
    t += duration;
  }
  w.load.t.push_back(t + 10'000 * kMs);  // idle after the run, so the last frames have samples after them
  w.load.p.push_back(idle);
  for (const FrameInterval& f : w.frames) w.truth.push_back(w.load.energy(f.startNs, f.endNs));
  return w;
}

struct Errors {
  double meanAbsFrame = 0.0;  // mean |E_frame - true| / true
  double p95AbsFrame = 0.0;
  double total = 0.0;         // (sum of frames - true sum) / true sum
};

Errors account(const Workload& w, int64_t periodNs, SampleKind kind) {
  LedgerOptions o;
  o.kind = kind;
  EnergyLedger ledger(o);
  const int64_t phase = 137 * kMs % periodNs;  // the meter's ticks are not aligned with the frames
  const int64_t end = w.frames.back().endNs + 2 * periodNs;
  for (int64_t t = phase; t <= end; t += periodNs) {
    PowerSample s;
    s.tNs = t;
    s.watts = kind == SampleKind::instantaneous ? w.load.power(t)
                                                : w.load.energy(t - periodNs, t) / (static_cast<double>(periodNs) * 1e-9);
    ledger.addSample(s);
  }
  for (const FrameInterval& f : w.frames) ledger.addFrame(f);
  const auto out = ledger.finish();
  std::vector<double> rel;
  double sum = 0.0, truthSum = 0.0;
  for (size_t i = 0; i < out.size(); ++i) {
    if (!out[i].known) continue;  // the first frames before the first 1 Hz tick
    rel.push_back(std::abs(out[i].joules - w.truth[i]) / w.truth[i]);
    sum += out[i].joules;
    truthSum += w.truth[i];
  }
  Errors e;
  for (double r : rel) e.meanAbsFrame += r / static_cast<double>(rel.size());
  std::sort(rel.begin(), rel.end());
  e.p95AbsFrame = rel[rel.size() * 95 / 100];
  e.total = (sum - truthSum) / truthSum;
  return e;
}

}  // namespace

TEST_CASE("sampling error: 1 Hz against 200 Hz on a synthetic load trace", "[power][ledger][sampling]") {
  const Workload w = makeWorkload();
  REQUIRE(w.frames.size() > 1500);
  const Errors point1 = account(w, 1000 * kMs, SampleKind::instantaneous);
  const Errors point200 = account(w, 5 * kMs, SampleKind::instantaneous);
  const Errors avg1 = account(w, 1000 * kMs, SampleKind::intervalAverage);
  const Errors avg200 = account(w, 5 * kMs, SampleKind::intervalAverage);
  std::printf("sampling error on %zu frames (60 s, ~30 fps, busy/idle per frame):\n", w.frames.size());
  std::printf("  meter model              rate    per-frame mean |err|   p95 |err|   run total err\n");
  auto row = [](const char* model, const char* rate, const Errors& e) {
    std::printf("  %-24s %-7s %8.2f %%             %6.2f %%    %+8.3f %%\n", model, rate, 100 * e.meanAbsFrame,
                100 * e.p95AbsFrame, 100 * e.total);
  };
  row("instantaneous (linear)", "1 Hz", point1);
  row("instantaneous (linear)", "200 Hz", point200);
  row("interval average (step)", "1 Hz", avg1);
  row("interval average (step)", "200 Hz", avg200);

  // Per-frame joules need the fast meter; run totals are good at either rate.
  CHECK(point1.meanAbsFrame > 3 * point200.meanAbsFrame);
  CHECK(avg1.meanAbsFrame > 3 * avg200.meanAbsFrame);
  CHECK(point200.meanAbsFrame < 0.10);
  CHECK(avg200.meanAbsFrame < 0.03);
  CHECK(std::abs(avg1.total) < 0.005);
  CHECK(std::abs(avg200.total) < 0.001);
  CHECK(std::abs(point1.total) < 0.05);
  CHECK(std::abs(point200.total) < 0.005);
}
