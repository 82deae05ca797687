#pragma once
// The one place where power becomes energy. Samples (from any meter) and frame intervals (from the SLAM loop)
// go in, in time order; per-frame joules come out once a sample at or after the frame's end has arrived, so
// results may lag the frames. Power between samples is interpolated linearly (instantaneous meters) or held
// piecewise constant (interval-average meters: energy counters). Any part of a frame that falls in a meter
// gap, before the first sample, or into data already discarded makes the frame unknown: never guessed.
//
// Not thread-safe: PowerSampler (power_sampler.h) wraps it for concurrent use.

#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "power/sample.h"

namespace sb::power {

struct LedgerOptions {
  SampleKind kind = SampleKind::instantaneous;
  int64_t maxSampleSpacingNs = 0;   // two samples farther apart than this enclose a gap (0 = no limit)
  double idleWatts = 0.0;           // W: baseline subtracted in FrameEnergy::joulesAboveIdle and the totals
  int64_t retainNs = 60'000'000'000;  // samples kept this long behind the newest (frames reported late)
};

struct EnergyTotals {
  uint64_t frames = 0;              // frames resolved (known + unknown)
  uint64_t knownFrames = 0;
  uint64_t unknownFrames = 0;
  double joules = 0.0;              // J, sum over known frames
  double joulesAboveIdle = 0.0;     // J, sum over known frames of (joules - idle W x duration)
  double seconds = 0.0;             // s, sum of the known frames' durations
  double idleWatts = 0.0;           // W, the baseline in use
  // The run as a whole: from the first frame's start to the last resolved frame's end, time between frames
  // included. At a 1 Hz meter these are exact where per-frame joules are interpolations.
  double spanSeconds = 0.0;         // s, wall time of the span
  double spanKnownSeconds = 0.0;    // s, of it covered by samples (not in a gap)
  double spanJoules = 0.0;          // J over the covered part

  double meanWatts() const { return seconds > 0.0 ? joules / seconds : NAN; }
  double joulesPerFrame() const { return knownFrames > 0 ? joules / static_cast<double>(knownFrames) : NAN; }
  double spanMeanWatts() const { return spanKnownSeconds > 0.0 ? spanJoules / spanKnownSeconds : NAN; }
};

// Energy over an interval and how much of it the samples cover.
struct Coverage {
  double joules = 0.0;   // J over the covered part
  int64_t knownNs = 0;   // covered by samples
  int64_t unknownNs = 0; // in a gap, before the first retained sample or after the last
  bool complete() const { return unknownNs == 0; }
};

class EnergyLedger {
 public:
  explicit EnergyLedger(LedgerOptions options = {});

  // A sample later than the previous one; returns false (and counts it) when it is not later.
  bool addSample(const PowerSample& sample);

  // The meter stopped delivering data (unplugged, silent): nothing is known after the last sample until the
  // next one, which starts a new stretch. Frames that reach past the last sample resolve as unknown now.
  void meterLost(const std::string& reason);

  // A frame's processing interval. Frames should arrive in order; results come out in the same order.
  void addFrame(const FrameInterval& frame);

  // Frames resolved since the last call, in the order they were added.
  std::vector<FrameEnergy> takeReady();

  // End of run: resolves what the samples allow and marks every other pending frame unknown with `reason`.
  std::vector<FrameEnergy> finish(const std::string& reason = "no power sample after the frame's end");

  Coverage energyBetween(int64_t startNs, int64_t endNs) const;

  const EnergyTotals& totals() const { return totals_; }
  const LedgerOptions& options() const { return options_; }
  void setIdleWatts(double watts);
  size_t pendingFrames() const { return pending_.size(); }
  bool hasReady() const { return !ready_.empty(); }
  bool lost() const { return lost_; }
  bool hasSamples() const { return !samples_.empty(); }
  int64_t lastSampleNs() const { return samples_.empty() ? 0 : samples_.back().tNs; }
  uint64_t droppedSamples() const { return dropped_; }

 private:
  struct Stored {
    int64_t tNs;
    double watts;
    bool knownBefore;  // the segment (previous sample, this sample] is covered
  };

  void resolve();
  void emit(const FrameInterval& f, const Coverage& c, const std::string& unknownReason);
  void extendSpan(int64_t toNs);
  void prune();
  double segmentEnergy(size_t i, int64_t x0, int64_t x1) const;

  LedgerOptions options_;
  std::deque<Stored> samples_;
  std::deque<FrameInterval> pending_;
  std::vector<FrameEnergy> ready_;
  EnergyTotals totals_;
  bool lost_ = false;
  std::string lostReason_;
  bool anySample_ = false;
  int64_t firstSampleNs_ = 0;
  bool spanStarted_ = false;
  int64_t spanStartNs_ = 0;
  int64_t spanCursorNs_ = 0;
  uint64_t dropped_ = 0;
};

}  // namespace sb::power
