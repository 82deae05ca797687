#pragma once
// SVG plots of `slambooster bench`: grouped bars (one group per sequence, one bar per controller) and the
// per-frame trace figure of one run (ITE, csr knob, trigger activity; the paper's mr1 figure).

#include <string>
#include <vector>

namespace sb::cli {

struct BarChart {
  std::string title, unit;
  std::vector<std::string> groups, series;  // x groups (sequences), bars per group (controllers)
  std::vector<std::vector<double>> values;  // [group][series], NaN = missing
  double limit = 0.0;                       // a dashed horizontal line (e.g. the 5 cm bound), 0 = none
};
void writeBarChart(const std::string& path, const BarChart& chart);

struct FrameTrace {
  std::string title;
  std::vector<double> iteCm;                 // per frame
  std::vector<int> csr;                      // per frame
  std::vector<std::string> triggerNames;     // rows of the trigger raster
  std::vector<std::vector<bool>> triggers;   // [row][frame]
};
void writeTraceFigure(const std::string& path, const FrameTrace& trace);

}  // namespace sb::cli
