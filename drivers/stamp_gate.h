#pragma once
// Frame stamps as trajectory.tum's reader takes them back (issue 44 P8, G4): core/trajectory.h reads
// "%.6f" stamps and refuses one that does not increase, so a frame whose stamp is not finite, outside
// [0, kMaxStampSeconds], or not later than the previous frame's by the microsecond trajectory.tum keeps, would
// make an output that `slambooster eval` refuses. Sources that take stamps from outside (the push source, a
// bag) pass each through a StampGate and drop (refuse) a frame it refuses, saying so; the TUM reader itself
// refuses the whole file (drivers/tum_index.cpp).

#include <optional>
#include <string>

namespace sb {

// Latest stamp accepted, seconds: about the year 2286 (a Unix time; "%.6f" stays 17 characters).
constexpr double kMaxStampSeconds = 1e10;

class StampGate {
 public:
  // Nothing when `seconds` is accepted (and remembered as the previous stamp); else why it is refused.
  std::optional<std::string> check(double seconds);
  size_t refused() const { return refused_; }

 private:
  std::optional<long long> previousMicros_;
  size_t refused_ = 0;
};

}  // namespace sb
