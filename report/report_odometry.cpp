// The odometry section of a run report: the wheels against the view (top view, per-frame disagreement with the
// fusion's verdicts), what the run learnt about the wheels, and how much of the run rode on them alone.

#include <cmath>

#include "report/odometry_view.h"
#include "report/run_sections.h"
#include "report/text_escape.h"
#include "report/trajectory_view.h"

namespace sb::report {

namespace {

using nlohmann::json;

TableCell number(double v, const std::string& key, int digits = 4) {
  return {std::isfinite(v) ? formatNumber(v, digits) : "-", std::isfinite(v) ? key : "", true};
}

// summary.json's "odometry" as written (keys the typed summary does not know included): the final values.
void finalValuesTable(HtmlPage& page, const RunData& run) {
  if (!run.summaryJson.is_object() || !run.summaryJson.contains("odometry") || !run.summaryJson["odometry"].is_object())
    return;
  Table t{{"at the end of the run", "value", "unit"}, {}};
  for (const auto& [key, value] : run.summaryJson["odometry"].items()) {
    if (value.is_structured()) {
      t.rows.push_back({{key}, {value.dump()}, {""}});
    } else if (value.is_number_float()) {
      t.rows.push_back({{key}, number(value.get<double>(), "", 5), {unitOfKey(key)}});
    } else {
      t.rows.push_back({{key}, {value.is_string() ? value.get<std::string>() : value.dump(), "", value.is_number()},
                        {unitOfKey(key)}});
    }
  }
  page.table(t, "summary");
}

void topView(HtmlPage& page, const RunData& run, const WheelsAgainstRun& w) {
  const TopView view = chooseTopView(run);
  XyPlot plot;
  plot.title = "Wheels, estimate" + std::string(run.groundTruth.empty() ? "" : " and ground truth") + " (top view)";
  plot.xLabel = view.xLabel;
  plot.yLabel = view.yLabel;
  plot.size = {820, 420};
  if (!run.groundTruth.empty()) plot.series.push_back(groundTruthSeries(run, view));
  if (!run.trajectory.empty()) plot.series.push_back(estimateSeries(run, view, run.ate ? "estimate (aligned)" : "estimate"));
  Series wheels{"wheels", {}, {}, "#e69f00"};
  for (const Eigen::Vector3d& p : w.wheelsPath) {
    const Eigen::Vector3d q = run.ate && p.allFinite() ? Eigen::Vector3d(run.ate->alignment * p) : p;
    wheels.x.push_back(q[view.axisX]);
    wheels.y.push_back(q[view.axisY]);
  }
  plot.series.push_back(wheels);
  page.figure(svgXyPlot(plot),
              "The wheels' camera path (" + run.wheelsPath +
                  ") started at the estimate's first pose and moved by the estimate's alignment" +
                  (run.ate ? " to the ground truth" : "") +
                  ": where the orange line leaves the others, the wheels' distance or heading is off.");
}

void disagreementPlot(HtmlPage& page, const WheelsAgainstRun& w, const std::vector<EventMarks>& lanes) {
  LinePlot plot;
  plot.title = "Wheels' step against the run's, per frame";
  plot.xLabel = "frame";
  plot.yLabel = "cm  /  deg";
  plot.yMin = 0.0;
  plot.size = {820, 300};
  plot.series.push_back({"translation (cm)", w.frame, w.translationCm, "#0072b2"});
  plot.series.push_back({"rotation (deg)", w.frame, w.rotationDeg, "#d55e00", LineStyle::line, 1.0});
  plot.series.push_back({"wheels' step (cm)", w.frame, w.wheelsStepCm, "#999999", LineStyle::line, 1.0, true});
  plot.events = lanes;
  page.figure(svgLinePlot(plot),
              "Between each frame and the one before: how far the wheels' camera step differs from the run's final "
              "pose's step (translation, cm; rotation, deg), the wheels' own step dashed. The lanes above are the "
              "fusion's verdicts from frames.jsonl. Where the wheels were used the two agree by construction; a "
              "slip (rejected) or a stall (wheels still, camera moving, or the reverse) stands out as a spike.");
}

void lanesOnly(HtmlPage& page, const RunData& run, const std::vector<EventMarks>& lanes) {
  LinePlot plot;
  plot.title = "The fusion's verdicts per frame";
  plot.xLabel = "frame";
  plot.yLabel = "m/frame";
  plot.size = {820, 200};
  plot.series.push_back({"camera speed", run.frames.frame, run.frames.velocity, "#0072b2"});
  plot.events = lanes;
  page.figure(svgLinePlot(plot), "Verdicts from frames.jsonl's \"odometry\" over the camera's speed.");
}

}  // namespace

void addOdometrySection(HtmlPage& page, const RunData& run) {
  page.heading(2, "Odometry", "odometry");
  const bool summarised = run.summary && run.summary->odometry;
  if (!summarised && !run.frames.recordsOdometry) {
    page.paragraph("No odometry: the run had none (summary.json has no \"odometry\" and frames.jsonl no "
                   "\"odometry\" objects).",
                   "muted");
    return;
  }
  const WheelsAgainstRun w = compareWheels(run);
  const std::vector<EventMarks> lanes = odometryVerdictLanes(run.frames);

  // How much of the run rode on the wheels, and the verdicts' counts.
  Table share{{"measure", "value", "unit"}, {}};
  const double frames = double(run.frames.size());
  if (frames > 0) {
    share.rows.push_back({{"frames on the wheels alone (dead reckoning)"},
                          number(double(w.wheelsOnlyFrames), "wheels.only_frames"), {"frames"}});
    share.rows.push_back({{"share of the frames"},
                          number(100.0 * double(w.wheelsOnlyFrames) / frames, "wheels.only_percent", 3), {"%"}});
  }
  if (!run.wheels.empty()) {
    share.rows.push_back({{"metres on the wheels alone"}, number(w.wheelsOnlyM, "wheels.only_m", 4), {"m"}});
    if (summarised && run.summary->odometry->pathM > 0)
      share.rows.push_back({{"share of the wheels' path"},
                            number(100.0 * w.wheelsOnlyM / run.summary->odometry->pathM, "wheels.only_path_percent", 3),
                            {"%"}});
  }
  for (const auto& lane : lanes)
    share.rows.push_back({{"frames marked " + lane.name}, number(double(lane.x.size()), "wheels.lane." + lane.name), {"frames"}});
  page.table(share, "headline");

  if (run.wheels.empty()) {
    page.paragraph("No wheels' path: " + run.wheelsWhy + ".", "muted");
    if (!lanes.empty()) lanesOnly(page, run, lanes);
  } else {
    topView(page, run, w);
    if (w.frame.empty())
      page.paragraph("No disagreement plot: no two consecutive frames have both a pose in frames.jsonl and a wheels' "
                     "pose in " + run.wheelsPath + " (do the stamps share a clock?).",
                     "muted");
    else
      disagreementPlot(page, w, lanes);
  }

  // Numeric fields of "odometry" (drift_m today; whatever the fusion logs per frame tomorrow).
  for (const Series& s : odometryNumberSeries(run.frames)) {
    bool varies = false;
    for (double v : s.y) varies |= std::isfinite(v) && v != 0.0;
    if (!varies) {  // a flat zero line says nothing a sentence cannot
      page.paragraph("odometry." + s.name + ": 0 on every frame.", "muted");
      continue;
    }
    LinePlot plot;
    plot.title = "odometry." + s.name + " per frame";
    plot.xLabel = "frame";
    plot.yLabel = unitOfKey(s.name).empty() ? s.name : unitOfKey(s.name);
    plot.size = {820, 180};
    plot.series.push_back(s);
    page.figure(svgLinePlot(plot), s.name == "drift_m" ? "Metres driven on the wheels alone since depth last tracked." : "");
  }

  const std::vector<ReasonCount> reasons = odometryReasons(run.frames);
  if (!reasons.empty()) {
    Table t{{"why (frames.jsonl odometry.why, digits masked when grouping)", "frames", "first", "last"}, {}};
    for (const auto& r : reasons)
      t.rows.push_back({{r.example}, number(double(r.frames), ""), number(r.first, ""), number(r.last, "")});
    page.table(t);
  }

  page.heading(3, "What the run learnt about the wheels");
  bool perFrame = false;
  for (const auto& c : run.frames.odometry) perFrame |= !c.boolean && c.name != "drift_m";
  page.paragraph(perFrame ? "The values the fusion logs per frame are plotted above; the final ones below (summary.json)."
                          : "frames.jsonl does not log the learnt calibration per frame: only its final values are "
                            "known (summary.json \"odometry\"). scale_error: the wheels read (1 + this) times the "
                            "distance; yaw_scale_error: the turns (1 + this) times; yaw_bias_deg_per_s: their drift.",
                 "muted");
  finalValuesTable(page, run);
}

}  // namespace sb::report
