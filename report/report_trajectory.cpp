// Trajectory top view and per-frame error sections of a run report.

#include "core/tracking_state.h"
#include "report/run_sections.h"
#include "report/text_escape.h"
#include "report/trajectory_view.h"

namespace sb::report {

void addTrajectorySection(HtmlPage& page, const RunData& run) {
  page.heading(2, "Trajectory", "trajectory");
  if (run.trajectory.empty() && run.groundTruth.empty()) {
    page.paragraph("No trajectory to show (trajectory.tum is missing or unreadable).", "muted");
    return;
  }
  const TopView view = chooseTopView(run);
  XyPlot plot;
  plot.title = "Top view (" + view.dropped + " axis dropped: the smallest extent)";
  plot.xLabel = view.xLabel;
  plot.yLabel = view.yLabel;
  if (!run.groundTruth.empty()) plot.series.push_back(groundTruthSeries(run, view));
  if (!run.trajectory.empty())
    plot.series.push_back(estimateSeries(run, view, run.ate ? "estimate (aligned)" : "estimate (volume frame)"));
  std::string caption;
  if (run.ate)
    caption = "Estimate rigidly aligned to the ground truth (Horn, " + std::to_string(run.ate->matches) +
              " matched poses); ATE RMSE " + formatNumber(run.ate->rmse * 100, 4) + " cm.";
  else if (run.groundTruth.empty())
    caption = "No ground truth: the estimate is shown in the volume frame.";
  else
    caption = "The estimate could not be aligned to the ground truth (see the problems above).";
  page.figure(svgXyPlot(plot), caption);
}

namespace {

// The tracking state as a band of lanes over the plot (weak, lost and relocalised frames; good ones are left
// blank). Returns a caption sentence, empty when the log records no state.
std::string addStateBand(LinePlot& plot, const FrameLog& f) {
  if (!f.hasColumn(f.state)) return "";
  std::vector<double> weak, lost, relocalised, odometry;
  for (size_t i = 0; i < f.size(); ++i) {
    if (f.state[i] == static_cast<double>(TrackingState::weak)) weak.push_back(f.frame[i]);
    if (f.state[i] == static_cast<double>(TrackingState::lost)) lost.push_back(f.frame[i]);
    if (f.state[i] == static_cast<double>(TrackingState::relocalised)) relocalised.push_back(f.frame[i]);
    if (f.state[i] == static_cast<double>(TrackingState::odometry)) odometry.push_back(f.frame[i]);
  }
  plot.events.push_back({"weak", weak, "#E69F00"});
  plot.events.push_back({"lost", lost, "#D55E00"});
  plot.events.push_back({"relocalised", relocalised, "#009E73"});
  std::string odometryText;
  if (!odometry.empty()) {  // only runs with odometry: the others' reports stay as they were
    plot.events.push_back({"odometry", odometry, "#56B4E9"});
    odometryText = ", " + std::to_string(odometry.size()) + " on odometry alone";
  }
  return " Tracking state marked above the curves: " + std::to_string(weak.size()) + " weak, " +
         std::to_string(lost.size()) + " lost, " + std::to_string(relocalised.size()) + " relocalised frames" +
         odometryText + ".";
}

}  // namespace

void addErrorSection(HtmlPage& page, const RunData& run) {
  page.heading(2, "Per-frame error", "ite");
  if (run.ate) {
    LinePlot plot;
    plot.title = "Instantaneous trajectory error (ITE)";
    plot.xLabel = "frame";
    plot.yLabel = "error (cm)";
    plot.series.push_back(iteSeries(run, false, "aligned (ATE per frame)"));
    Series unaligned = iteSeries(run, true, "unaligned (paper's measure)");
    unaligned.dashed = true;
    plot.series.push_back(std::move(unaligned));
    plot.yMin = 0.0;
    const std::string band = addStateBand(plot, run.frames);
    page.figure(svgLinePlot(plot), "Aligned: |alignment * p_est - p_gt| per matched frame. Unaligned: both "
                                   "trajectories relative to their first matched pose (mean " +
                                       formatNumber(run.ate->unalignedMean * 100, 4) + " cm)." + band);
  } else {
    page.paragraph("No per-frame error: it needs a ground truth (pass --groundtruth FILE).", "muted");
  }
  const FrameLog& f = run.frames;
  if (f.hasColumn(f.velocity)) {
    LinePlot plot;
    plot.title = "Camera speed (the controller's ITE proxy)";
    plot.xLabel = "frame";
    plot.yLabel = "cm/frame";
    Series s{"velocity", f.frame, f.velocity, "", LineStyle::line, 1.2, false};
    for (double& v : s.y) v *= 100.0;
    plot.series.push_back(std::move(s));
    plot.yMin = 0.0;
    plot.size.height = 200;
    page.figure(svgLinePlot(plot), "Translation between consecutive poses, from frames.jsonl.");
  }
}

}  // namespace sb::report
