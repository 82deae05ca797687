#include "tools/slambooster/bench_plots.h"

#include <algorithm>
#include <cmath>

#include "pipeline/knobs.h"
#include "report/run_data.h"
#include "report/svg_writer.h"
#include "report/trajectory_view.h"

namespace sb::cli {

namespace {

constexpr double kAteBoundCm = 5.0;  // the paper's accuracy requirement

report::BarChart bars(const BenchResults& r, const std::string& title, const std::string& yLabel, bool ate) {
  report::BarChart chart;
  chart.title = title;
  chart.yLabel = yLabel;
  chart.categories = r.sequences;
  for (const std::string& label : r.columns) {
    report::BarGroup group{label, {}};
    for (const std::string& name : r.sequences) {
      const BenchCell c = r.cell(name, label);
      group.values.push_back(!c.present ? NAN : ate ? c.ateM * 100 : c.ms);
    }
    chart.groups.push_back(group);
  }
  chart.valueLabels = r.sequences.size() * r.columns.size() <= 24;  // labels overlap beyond that
  chart.size = {820, 320};
  return chart;
}

}  // namespace

std::string svgBenchTimeBars(const BenchResults& results) {
  return report::svgBarChart(bars(results, "Computation time per frame", "ms/frame", false));
}

std::string svgBenchAteBars(const BenchResults& results) {
  report::BarChart chart = bars(results, "ATE RMSE", "cm", true);
  chart.limit = kAteBoundCm;
  chart.limitName = "5 cm bound";
  return report::svgBarChart(chart);
}

BenchTrace benchTrace(const std::string& runDir, const std::string& reference, const std::string& title) {
  BenchTrace trace;
  report::RunLoadOptions options;
  options.groundTruth = reference;
  const report::RunData run = report::loadRun(runDir, options);
  // A run whose trajectory cannot be aligned (lost from the first frame: every position the same) still gets
  // its knob and trigger trace (loadRun lists why); its ATE is already n/a in the tables.
  trace.problems = run.problems;
  const report::FrameLog& f = run.frames;

  std::vector<report::EventMarks> triggers;
  for (const auto& t : f.triggers) triggers.push_back({t.name, t.frames, ""});

  report::LinePlot ite;
  ite.title = title + ": per-frame error (ITE)";
  ite.xLabel = "frame";
  ite.yLabel = "ITE cm";
  ite.series.push_back(report::iteSeries(run, false, "ITE"));
  ite.series.back().color = "#0072B2";
  ite.yMin = 0.0;
  ite.events = triggers;
  ite.size.height = 220 + 9 * static_cast<double>(triggers.size());
  trace.plots.push_back(ite);

  report::LinePlot csr;
  csr.title = title + ": csr (compute size ratio)";
  csr.xLabel = "frame";
  csr.yLabel = knobKey(&Knobs::csr).name;
  std::vector<double> level;
  for (double v : f.csr) level.push_back(std::isfinite(v) && v > 0 ? std::log2(v) : NAN);
  csr.series.push_back({"", f.frame, level, "#D55E00", report::LineStyle::step, 1.8, false});
  csr.yTicks = {{0, "1"}, {1, "2"}, {2, "4"}, {3, "8"}};
  csr.yMin = 0.0;
  csr.yMax = 3.0;
  csr.events = triggers;
  csr.size.height = 190 + 9 * static_cast<double>(triggers.size());
  trace.plots.push_back(csr);
  return trace;
}

std::string svgStacked(const std::vector<report::LinePlot>& plots) {
  double width = 0, height = 0;
  for (const auto& p : plots) {
    width = std::max(width, p.size.width);
    height += p.size.height;
  }
  report::SvgWriter svg(width, height, plots.empty() ? "" : plots.front().title);
  double y = 0;
  for (const auto& p : plots) {
    svg.embed(0, y, report::svgLinePlot(p));
    y += p.size.height;
  }
  return svg.str();
}

}  // namespace sb::cli
