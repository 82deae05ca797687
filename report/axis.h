#pragma once
// Axis ranges and tick positions with "nice" numbers (1, 2, 5 times a power of ten), and tick labels that
// show just enough decimals for the step.

#include <string>
#include <vector>

namespace sb::report {

struct Axis {
  double min = 0, max = 1;     // the drawn range (tick-aligned unless fixed by the caller)
  double step = 0.2;           // tick spacing
  std::vector<double> ticks;   // tick values inside [min, max]
  std::vector<std::string> labels;  // one per tick
};

// The nice number closest to `x` (round = true) or the smallest nice number >= x (round = false); x > 0.
double niceNumber(double x, bool round);

// An axis covering [lo, hi] with about `targetTicks` ticks; the range is widened to whole steps. Non-finite
// bounds or lo > hi give [0, 1]; lo == hi is widened around the value.
Axis niceAxis(double lo, double hi, int targetTicks = 6);

// Ticks and labels inside the fixed range [lo, hi] (the range is not widened), for equal-aspect plots.
Axis niceTicksWithin(double lo, double hi, int targetTicks = 6);

// Ticks at whole multiples of `step` (> 0) inside the fixed range [lo, hi].
Axis ticksWithin(double lo, double hi, double step);

// Label of `value` on an axis with tick spacing `step`: fixed decimals derived from the step, or the %g form
// for very large / small magnitudes; "-0" never appears.
std::string tickLabel(double value, double step);

}  // namespace sb::report
