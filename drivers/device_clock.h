#pragma once
// Maps a device's frame timestamps (its own clock, microseconds) onto the host's CLOCK_MONOTONIC (seconds).
//
// The offset host - device is estimated as the smallest (host arrival time - device timestamp) seen so far:
// every frame arrives after it was stamped, so the smallest difference is the one with the least transfer
// delay. The estimate may rise by `driftPpm` of the elapsed time (a device clock slower than the host), and
// falls at once when a frame arrives sooner than expected (a faster device clock). A device timestamp that
// goes backwards (the device restarted) starts the estimate afresh. The mapped times strictly increase over
// the whole lifetime of one DeviceClock, across resets.

#include <cstdint>
#include <optional>

namespace sb {

class DeviceClock {
 public:
  explicit DeviceClock(double driftPpm = 100.0) : driftPpm_(driftPpm) {}

  // The CLOCK_MONOTONIC time (seconds) of a frame stamped `deviceMicros` by the device, which arrived at
  // host time `hostSeconds` (CLOCK_MONOTONIC).
  double map(uint64_t deviceMicros, double hostSeconds);
  // Forgets the offset (a new connection: the device clock may have restarted); monotonicity is kept.
  void reset() { offset_.reset(); }
  // The current offset estimate (host - device, seconds), if any frame has been seen since the last reset.
  std::optional<double> offset() const { return offset_; }

  // CLOCK_MONOTONIC now, seconds.
  static double monotonicNow();

 private:
  double driftPpm_;
  std::optional<double> offset_;
  double lastDevice_ = 0.0;     // seconds
  double lastHost_ = 0.0;       // seconds, arrival time of the previous frame
  std::optional<double> lastMapped_;
};

}  // namespace sb
