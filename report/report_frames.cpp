// Per-frame sections of a run report: knob activity, stage times, energy.

#include <algorithm>
#include <cmath>
#include <numeric>

#include "pipeline/knobs.h"
#include "report/plots.h"
#include "report/run_sections.h"
#include "report/text_escape.h"

namespace sb::report {

namespace {

// icp thresholds span decades and include 0: plotted as log10, with 0 drawn one decade below 1e-6.
constexpr double kIcpZeroLevel = -7;

std::vector<double> icpLevels(const std::vector<double>& icp) {
  std::vector<double> y;
  for (double v : icp) y.push_back(!std::isfinite(v) ? v : v <= 0 ? kIcpZeroLevel : std::max(kIcpZeroLevel, std::log10(v)));
  return y;
}

std::vector<double> failedTrackFrames(const FrameLog& f) {
  std::vector<double> frames;
  for (size_t i = 0; i < f.size(); ++i) {
    const bool attempted = !std::isfinite(f.trackingAttempted[i]) || f.trackingAttempted[i] != 0;
    if (attempted && f.tracked[i] == 0) frames.push_back(f.frame[i]);
  }
  return frames;
}

LinePlot knobPlot(const std::string& title, const std::string& yLabel, const FrameLog& f, std::vector<double> y) {
  LinePlot p;
  p.title = title;
  p.xLabel = "frame";
  p.yLabel = yLabel;
  p.series.push_back({"", f.frame, std::move(y), "#0072B2", LineStyle::step, 1.8, false});
  p.size.height = 170;
  return p;
}

// Stage indices in pipeline order (architecture.md D2 names); stages the report does not know follow
// in log order. JSON objects come back sorted by key, which would scramble the stack.
std::vector<size_t> pipelineOrder(const std::vector<std::string>& names) {
  static const char* const kOrder[] = {"mm2meters", "bilateralFilter", "halfSampleRobust", "depth2vertex", "vertex2normal",
                                       "track",     "reduce",          "integrate",        "raycast",      "render"};
  std::vector<size_t> order;
  for (const char* known : kOrder)
    for (size_t s = 0; s < names.size(); ++s)
      if (names[s] == known) order.push_back(s);
  for (size_t s = 0; s < names.size(); ++s)
    if (std::find(order.begin(), order.end(), s) == order.end()) order.push_back(s);
  return order;
}

}  // namespace

void addKnobSection(HtmlPage& page, const RunData& run) {
  page.heading(2, "Knob activity", "knobs");
  const FrameLog& f = run.frames;
  if (f.size() == 0) {
    page.paragraph("No per-frame log to show (see the problems above).", "muted");
    return;
  }
  LinePlot csr = knobPlot("csr (compute size ratio)", knobKey(&Knobs::csr).name, f, f.csr);
  for (double& v : csr.series[0].y) v = std::isfinite(v) && v > 0 ? std::log2(v) : std::nan("");
  csr.yTicks = {{0, "1"}, {1, "2"}, {2, "4"}, {3, "8"}};
  std::string caption;
  if (f.recordsTriggers) {
    // Surface and correction first (the paper's figure), then any other trigger that fired.
    csr.events.push_back({"surface", f.triggerFrames("surface"), "#009E73"});
    csr.events.push_back({"correction", f.triggerFrames("correction"), "#D55E00"});
    for (const auto& t : f.triggers)
      if (t.name != "surface" && t.name != "correction") csr.events.push_back({t.name, t.frames, ""});
    for (const auto& e : csr.events) caption += e.name + " " + std::to_string(e.x.size()) + "x, ";
  } else {
    caption = "the log records no controller triggers, ";
  }
  const std::vector<double> failed = failedTrackFrames(f);
  if (!failed.empty()) csr.events.push_back({"tracking failed", failed, "#CC79A7"});
  caption += "tracking failed " + std::to_string(failed.size()) + "x.";
  csr.size.height = 190 + 9 * static_cast<double>(csr.events.size());
  page.figure(svgLinePlot(csr), "Marks along the top, frames where: " + caption);

  if (f.hasColumn(f.level)) {
    LinePlot level = knobPlot("Approximation level (0 = most accurate)", "level", f, f.level);
    level.yMin = 0.0;
    page.figure(svgLinePlot(level));
  }

  LinePlot icp = knobPlot("icp (ICP early-stop threshold)", knobKey(&Knobs::icpThreshold).name, f, icpLevels(f.icp));
  for (int level = static_cast<int>(kIcpZeroLevel); level <= 0; ++level)
    icp.yTicks.push_back({level, level == kIcpZeroLevel ? "0" : level == 0 ? "1" : "1e" + std::to_string(level)});
  page.figure(svgLinePlot(icp));

  LinePlot pd0 = knobPlot("pd0 (max ICP iterations, finest level)", iterationsKey(0).name, f, f.pd0);
  pd0.yMin = 0.0;
  page.figure(svgLinePlot(pd0));
}

namespace {

constexpr size_t kMaxStackedPoints = 600;

// Means of `y` (finite values) over consecutive bins of `bin` samples, at the bins' mean x.
Series binnedMeans(const std::string& name, const std::vector<double>& x, const std::vector<double>& y, size_t bin) {
  Series out{name, {}, {}, "", LineStyle::line, 1, false};
  if (bin <= 1) {
    out.x = x;
    out.y = y;
    return out;
  }
  const size_t n = std::min(x.size(), y.size());
  for (size_t start = 0; start < n; start += bin) {
    double sx = 0, sy = 0;
    size_t nx = 0, ny = 0;
    for (size_t i = start; i < std::min(n, start + bin); ++i) {
      if (std::isfinite(x[i])) sx += x[i], ++nx;
      if (std::isfinite(y[i])) sy += y[i], ++ny;
    }
    out.x.push_back(nx ? sx / double(nx) : std::nan(""));
    out.y.push_back(ny ? sy / double(ny) : std::nan(""));
  }
  return out;
}

}  // namespace

void addStageTimeSection(HtmlPage& page, const RunData& run) {
  page.heading(2, "Time per frame", "stages");
  const FrameLog& f = run.frames;
  LinePlot stacked;
  stacked.title = "Per-stage time per frame (stacked)";
  stacked.xLabel = "frame";
  stacked.yLabel = "ms";
  stacked.stacked = true;
  BarChart means;
  means.title = "Mean time per stage";
  means.yLabel = "ms/frame";
  means.groups.push_back({run.label, {}, "#0072B2"});
  // Frames per point of the stacked areas: one filled polygon per stage costs two points per sample, so a long
  // log is drawn as means over bins of frames (1200 frames: 2) to keep the plot under 200 KB.
  const size_t bin = std::max<size_t>(1, (f.size() + kMaxStackedPoints - 1) / kMaxStackedPoints);
  for (size_t s : pipelineOrder(f.stageNames)) {
    double sum = 0;
    size_t n = 0;
    for (double v : f.stageMs[s])
      if (std::isfinite(v)) {
        sum += v;
        ++n;
      }
    if (sum <= 0) continue;  // stages that never ran (e.g. render in `run`) only clutter the legend
    stacked.series.push_back(binnedMeans(f.stageNames[s], f.frame, f.stageMs[s], bin));
    means.categories.push_back(f.stageNames[s]);
    means.groups[0].values.push_back(sum / static_cast<double>(n));
  }
  if (stacked.series.empty()) {
    page.paragraph("No stage times in the per-frame log.", "muted");
    return;
  }
  stacked.size.height = 300;
  page.figure(svgLinePlot(stacked), "Host-clock time of each stage, from frames.jsonl (key \"ms\")" +
                                        (bin > 1 ? "; each point the mean over " + std::to_string(bin) + " frames." : "."));
  means.size = {820, 280};
  means.valueLabels = true;
  page.figure(svgBarChart(means), "Mean over the frames in frames.jsonl.");
}

void addEnergySection(HtmlPage& page, const RunData& run) {
  const FrameLog& f = run.frames;
  const bool joules = f.hasColumn(f.joules), power = f.hasColumn(f.powerW);
  page.heading(2, "Energy", "energy");
  if (!joules && !power) {
    page.paragraph("No power meter was used for this run (no energy.jsonl, and frames.jsonl has no \"joules\" or "
                   "\"power_w\").",
                   "muted");
    return;
  }
  if (joules) {
    LinePlot p;
    p.title = "Energy per frame";
    p.xLabel = "frame";
    p.yLabel = "J";
    p.series.push_back({"joules", f.frame, f.joules, "#E69F00", LineStyle::line, 1.4, false});
    p.yMin = 0.0;
    page.figure(svgLinePlot(p), "Gaps are frames whose energy is unknown (meter gap).");
  }
  if (power) {
    LinePlot p;
    p.title = "Power";
    p.xLabel = "frame";
    p.yLabel = "W";
    p.series.push_back({"power", f.frame, f.powerW, "#D55E00", LineStyle::line, 1.4, false});
    page.figure(svgLinePlot(p));
  }
}

}  // namespace sb::report
