// The tracking-quality section of a run report: how well the geometry in view fixed the camera's motion.

#include <cmath>
#include <cstdio>

#include "report/plots.h"
#include "report/run_sections.h"

namespace sb::report {

namespace {

constexpr double kFloor = -5;  // log10 of the smallest conditioning drawn (0 is drawn here)

double threshold(const RunData& run) {
  return run.summary ? run.summary->constrainedMinConditioning() : NAN;
}

}  // namespace

void addTrackingQualitySection(HtmlPage& page, const RunData& run) {
  page.heading(2, "Tracking quality", "quality");
  const FrameLog& f = run.frames;
  if (!f.hasColumn(f.conditioning)) {
    page.paragraph("The per-frame log records no tracking quality (\"conditioning\"): the run predates it or ICP "
                   "never ran.",
                   "muted");
    return;
  }
  LinePlot p;
  p.title = "Conditioning of the view's structure (ICP rows summed per block; log scale)";
  p.xLabel = "frame";
  p.yLabel = "conditioning";
  std::vector<double> y;
  std::vector<double> unconstrained;
  size_t known = 0;
  for (size_t i = 0; i < f.size(); ++i) {
    const double c = f.conditioning[i];
    y.push_back(!std::isfinite(c) ? c : c <= 0 ? kFloor : std::max(kFloor, std::log10(c)));
    if (std::isfinite(c)) ++known;
    if (f.constrained[i] == 0) unconstrained.push_back(f.frame[i]);
  }
  p.series.push_back({"conditioning", f.frame, y, "#0072B2", LineStyle::line, 1.2, false});
  const double t = threshold(run);
  if (std::isfinite(t) && t > 0 && !f.frame.empty()) {
    const double ty = std::log10(t);
    p.series.push_back({"constrained threshold", {f.frame.front(), f.frame.back()}, {ty, ty}, "#D55E00",
                        LineStyle::line, 1.2, true});
  }
  p.events.push_back({"unconstrained", unconstrained, "#CC79A7"});
  for (int level = static_cast<int>(kFloor); level <= 0; ++level)
    p.yTicks.push_back({level, level == kFloor ? "0" : level == 0 ? "1" : "1e" + std::to_string(level)});
  p.yMin = kFloor;
  p.yMax = 0.0;
  p.size.height = 220;
  char caption[256];
  std::snprintf(caption, sizeof caption,
                "%zu of %zu frames with an ICP result were unconstrained (marked): the geometry in view did not fix "
                "every motion, so the pose may drift along the weakest one even where the frame counts as tracked.",
                unconstrained.size(), known);
  page.figure(svgLinePlot(p), caption);
}

}  // namespace sb::report
