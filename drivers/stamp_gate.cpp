#include "drivers/stamp_gate.h"

#include <cmath>
#include <cstdio>

namespace sb {

namespace {

std::string seconds(double t) {
  char text[64];
  std::snprintf(text, sizeof text, "%.6g", t);
  return text;
}

}  // namespace

std::optional<std::string> StampGate::check(double t) {
  std::optional<std::string> why;
  if (!std::isfinite(t) || t < 0 || t > kMaxStampSeconds) {
    why = "stamp " + seconds(t) + " s is outside [0, " + seconds(kMaxStampSeconds) + "] s";
  } else {
    const long long micros = std::llround(t * 1e6);  // the resolution of trajectory.tum's "%.6f"
    if (previousMicros_ && micros <= *previousMicros_) {
      char text[128];
      std::snprintf(text, sizeof text, "stamp %.6f s does not increase (previous %.6f s, at trajectory.tum's "
                    "microsecond)", t, *previousMicros_ * 1e-6);
      why = text;
    } else {
      previousMicros_ = micros;
    }
  }
  if (why) ++refused_;
  return why;
}

}  // namespace sb
