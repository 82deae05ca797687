#pragma once
// Figures of `slambooster bench`, drawn with report/'s plot functions: grouped bars per sequence (one bar
// per controller) of time and ATE, and the per-frame trace of one run (ITE, csr knob, the controller's
// triggers; the paper's mr1 figure). Each is a complete <svg> element, for report.html and the .svg files.

#include <string>
#include <vector>

#include "report/plots.h"
#include "tools/slambooster/bench_report.h"

namespace sb::cli {

// Computation ms/frame per sequence and controller (results.columns), NaN where a run is absent.
std::string svgBenchTimeBars(const BenchResults& results);
// ATE RMSE (cm) per sequence and controller, with the 5 cm bound dashed.
std::string svgBenchAteBars(const BenchResults& results);

struct BenchTrace {
  std::vector<report::LinePlot> plots;  // ITE over frames (triggers marked along the top), csr over frames
  std::vector<std::string> problems;    // why a part is missing (e.g. the trajectory cannot be aligned)
};
// The trace of the run in `runDir`, its ITE against the TUM trajectory `reference`. `title` names the run.
BenchTrace benchTrace(const std::string& runDir, const std::string& reference, const std::string& title);
// The plots stacked in one <svg> (trace.svg).
std::string svgStacked(const std::vector<report::LinePlot>& plots);

}  // namespace sb::cli
