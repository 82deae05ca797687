#include "power/energy_ledger.h"

#include <algorithm>
#include <cstdint>

namespace sb::power {

EnergyLedger::EnergyLedger(LedgerOptions options) : options_(options) { totals_.idleWatts = options_.idleWatts; }

void EnergyLedger::setIdleWatts(double watts) {
  options_.idleWatts = watts;
  totals_.idleWatts = watts;
}

bool EnergyLedger::addSample(const PowerSample& s) {
  if (!samples_.empty() && s.tNs <= samples_.back().tNs) {
    ++dropped_;
    return false;
  }
  bool known = !samples_.empty() && !s.gapBefore && !lost_;
  if (known && options_.maxSampleSpacingNs > 0 && s.tNs - samples_.back().tNs > options_.maxSampleSpacingNs)
    known = false;
  samples_.push_back(Stored{s.tNs, s.watts, known});
  if (!anySample_) {
    anySample_ = true;
    firstSampleNs_ = s.tNs;
  }
  lost_ = false;
  lostReason_.clear();
  resolve();
  return true;
}

void EnergyLedger::meterLost(const std::string& reason) {
  lost_ = true;
  lostReason_ = reason.empty() ? "meter gap" : reason;
  resolve();
}

void EnergyLedger::addFrame(const FrameInterval& frame) {
  if (!spanStarted_) {
    spanStarted_ = true;
    spanStartNs_ = spanCursorNs_ = frame.startNs;
  }
  pending_.push_back(frame);
  resolve();
}

std::vector<FrameEnergy> EnergyLedger::takeReady() {
  std::vector<FrameEnergy> out;
  out.swap(ready_);
  return out;
}

std::vector<FrameEnergy> EnergyLedger::finish(const std::string& reason) {
  resolve();
  while (!pending_.empty()) {
    const FrameInterval f = pending_.front();
    pending_.pop_front();
    emit(f, energyBetween(f.startNs, f.endNs), reason);
  }
  return takeReady();
}

double EnergyLedger::segmentEnergy(size_t i, int64_t x0, int64_t x1) const {
  const double dt = static_cast<double>(x1 - x0) * 1e-9;
  const Stored& b = samples_[i];
  if (options_.kind == SampleKind::intervalAverage) return dt * b.watts;
  const Stored& a = samples_[i - 1];
  const double span = static_cast<double>(b.tNs - a.tNs);
  const double slope = (b.watts - a.watts) / span;
  const double p0 = a.watts + slope * static_cast<double>(x0 - a.tNs);
  const double p1 = a.watts + slope * static_cast<double>(x1 - a.tNs);
  return dt * 0.5 * (p0 + p1);
}

Coverage EnergyLedger::energyBetween(int64_t startNs, int64_t endNs) const {
  Coverage c;
  if (endNs <= startNs) return c;
  // Segment i (i >= 1) is (samples_[i-1].tNs, samples_[i].tNs]; find the one holding startNs.
  auto it = std::upper_bound(samples_.begin(), samples_.end(), startNs,
                             [](int64_t t, const Stored& s) { return t < s.tNs; });
  size_t i = static_cast<size_t>(it - samples_.begin());
  int64_t x = startNs;
  if (i == 0) {  // before the first retained sample: nothing known
    const int64_t stop = samples_.empty() ? endNs : std::min(endNs, samples_.front().tNs);
    c.unknownNs += stop - x;
    x = stop;
    i = 1;
  }
  while (x < endNs) {
    if (i >= samples_.size()) {  // after the last sample: not (yet) known
      c.unknownNs += endNs - x;
      break;
    }
    const int64_t stop = std::min(endNs, samples_[i].tNs);
    if (samples_[i].knownBefore) {
      c.joules += segmentEnergy(i, x, stop);
      c.knownNs += stop - x;
    } else {
      c.unknownNs += stop - x;
    }
    x = stop;
    ++i;
  }
  return c;
}

void EnergyLedger::resolve() {
  while (!pending_.empty()) {
    const FrameInterval f = pending_.front();
    std::string reason;
    if (f.endNs < f.startNs) {
      reason = "frame ends before it starts";
    } else if (!anySample_ || samples_.back().tNs < f.endNs) {
      if (!lost_) break;  // wait for a sample at or after the frame's end
      reason = lostReason_;
    } else if (f.startNs < firstSampleNs_) {
      reason = "frame starts before the first power sample";
    } else if (f.startNs < samples_.front().tNs) {
      reason = "power samples for this frame were already discarded (frame reported too late)";
    }
    pending_.pop_front();
    const Coverage c = energyBetween(f.startNs, f.endNs);
    if (reason.empty() && !c.complete()) reason = "meter gap";
    emit(f, c, reason);
  }
  prune();
}

void EnergyLedger::emit(const FrameInterval& f, const Coverage& c, const std::string& unknownReason) {
  FrameEnergy e;
  e.frame = f.frame;
  e.startNs = f.startNs;
  e.endNs = f.endNs;
  const bool known = unknownReason.empty() && c.complete() && f.endNs >= f.startNs;
  ++totals_.frames;
  if (known) {
    const double seconds = nsToSeconds(f.endNs - f.startNs);
    e.known = true;
    e.joules = c.joules;
    e.joulesAboveIdle = c.joules - options_.idleWatts * seconds;
    e.meanWatts = seconds > 0.0 ? c.joules / seconds : NAN;
    ++totals_.knownFrames;
    totals_.joules += e.joules;
    totals_.joulesAboveIdle += e.joulesAboveIdle;
    totals_.seconds += seconds;
  } else {
    e.unknownReason = unknownReason.empty() ? "meter gap" : unknownReason;
    ++totals_.unknownFrames;
  }
  extendSpan(f.endNs);
  ready_.push_back(std::move(e));
}

void EnergyLedger::extendSpan(int64_t toNs) {
  if (toNs <= spanCursorNs_) return;
  const Coverage c = energyBetween(spanCursorNs_, toNs);
  totals_.spanJoules += c.joules;
  totals_.spanKnownSeconds += nsToSeconds(c.knownNs);
  spanCursorNs_ = toNs;
  totals_.spanSeconds = nsToSeconds(spanCursorNs_ - spanStartNs_);
}

void EnergyLedger::prune() {
  if (samples_.size() < 2) return;
  const int64_t newest = samples_.back().tNs;
  int64_t horizon = newest > INT64_MIN + options_.retainNs ? newest - options_.retainNs : INT64_MIN;
  if (spanStarted_) horizon = std::min(horizon, spanCursorNs_);
  for (const FrameInterval& f : pending_) horizon = std::min(horizon, f.startNs);
  // Keep the last sample at or before the horizon: it starts the segment that holds the horizon.
  while (samples_.size() >= 2 && samples_[1].tNs <= horizon) samples_.pop_front();
}

}  // namespace sb::power
