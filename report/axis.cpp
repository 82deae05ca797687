#include "report/axis.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace sb::report {

double niceNumber(double x, bool round) {
  const double exponent = std::floor(std::log10(x));
  const double base = std::pow(10.0, exponent);
  const double f = x / base;  // in [1, 10)
  double nice;
  if (round)
    nice = f < 1.5 ? 1 : f < 3 ? 2 : f < 7 ? 5 : 10;
  else
    nice = f <= 1 ? 1 : f <= 2 ? 2 : f <= 5 ? 5 : 10;
  return nice * base;
}

namespace {

void fillTicks(Axis& a, double firstTick) {
  a.ticks.clear();
  a.labels.clear();
  // Index-based so that accumulated rounding never adds or drops a tick.
  const double tolerance = a.step * 1e-6;
  for (int i = 0; i < 1000; ++i) {
    double t = firstTick + i * a.step;
    if (t > a.max + tolerance) break;
    if (std::fabs(t) < tolerance) t = 0;
    a.ticks.push_back(t);
    a.labels.push_back(tickLabel(t, a.step));
  }
}

bool sanitise(double& lo, double& hi) {
  if (!std::isfinite(lo) || !std::isfinite(hi) || lo > hi) {
    lo = 0;
    hi = 1;
    return false;
  }
  if (lo == hi) {
    const double pad = lo == 0 ? 1.0 : std::fabs(lo) * 0.1;
    lo -= pad;
    hi += pad;
  }
  return true;
}

}  // namespace

Axis niceAxis(double lo, double hi, int targetTicks) {
  sanitise(lo, hi);
  targetTicks = std::max(2, targetTicks);
  Axis a;
  const double range = niceNumber(hi - lo, false);
  a.step = niceNumber(range / (targetTicks - 1), true);
  a.min = std::floor(lo / a.step) * a.step;
  a.max = std::ceil(hi / a.step) * a.step;
  fillTicks(a, a.min);
  return a;
}

Axis niceTicksWithin(double lo, double hi, int targetTicks) {
  sanitise(lo, hi);
  targetTicks = std::max(2, targetTicks);
  return ticksWithin(lo, hi, niceNumber(niceNumber(hi - lo, false) / (targetTicks - 1), true));
}

Axis ticksWithin(double lo, double hi, double step) {
  sanitise(lo, hi);
  Axis a;
  a.min = lo;
  a.max = hi;
  a.step = step > 0 && std::isfinite(step) ? step : hi - lo;
  fillTicks(a, std::ceil(lo / a.step - 1e-9) * a.step);
  return a;
}

std::string tickLabel(double value, double step) {
  char buffer[48];
  const double magnitude = std::max(std::fabs(value), step);
  if (magnitude >= 1e6 || step < 1e-4) {
    std::snprintf(buffer, sizeof buffer, "%.3g", value);
  } else {
    const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
    std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  }
  std::string s = buffer;
  if (s.find_first_not_of("-0.") == std::string::npos) s = "0";  // "-0.0" and friends
  return s;
}

}  // namespace sb::report
