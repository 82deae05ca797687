#pragma once
// Where meters and the sampler get "now" from: CLOCK_MONOTONIC in production, a hand-driven clock in tests
// (so reconnect backoff and replay pacing are tested without sleeping).

#include <atomic>
#include <cstdint>

namespace sb::power {

class Clock {
 public:
  virtual ~Clock() = default;
  virtual int64_t nowNs() const = 0;  // CLOCK_MONOTONIC, nanoseconds
};

// The real CLOCK_MONOTONIC.
class MonotonicClock final : public Clock {
 public:
  int64_t nowNs() const override;
};

// The process-wide MonotonicClock (stateless; shared for convenience).
const Clock& monotonicClock();

// A clock that moves only when told to (tests, offline replay). Safe to read from another thread.
class ManualClock final : public Clock {
 public:
  explicit ManualClock(int64_t startNs = 1'000'000'000) : now_(startNs) {}
  int64_t nowNs() const override { return now_.load(); }
  void set(int64_t ns) { now_.store(ns); }
  void advance(int64_t ns) { now_.fetch_add(ns); }

 private:
  std::atomic<int64_t> now_;
};

}  // namespace sb::power
