#pragma once
// The sections of a run report. Each appends to the page; a section whose inputs are missing says so in one
// line instead of drawing an empty plot.

#include <string>

#include "report/html_page.h"
#include "report/run_data.h"

namespace sb::report {

// Headline numbers from summary.json (ATE in cm, ms/frame, tracked, J/frame) and the problems list.
void addOverviewSection(HtmlPage& page, const RunData& run);
// Top view of the estimate (aligned to the ground truth when there is one) against the ground truth.
void addTrajectorySection(HtmlPage& page, const RunData& run);
// Per-frame ITE (aligned and unaligned) and the camera speed.
void addErrorSection(HtmlPage& page, const RunData& run);
// csr, icp and pd0 per frame with the controller's triggers and failed tracks marked.
void addKnobSection(HtmlPage& page, const RunData& run);
// Tracking quality per frame: the ICP problem's conditioning against the constrained threshold, the frames
// whose geometry left a motion free marked.
void addTrackingQualitySection(HtmlPage& page, const RunData& run);
// Stacked per-stage time per frame and the mean per stage.
void addStageTimeSection(HtmlPage& page, const RunData& run);
// Joules and power per frame when a meter was used.
void addEnergySection(HtmlPage& page, const RunData& run);
// The rendered model and a link to the mesh (relative to `reportDir`, where the page is written).
void addMapSection(HtmlPage& page, const RunData& run, const std::string& reportDir);
// The wheels against the view: top view of wheels, estimate and truth; per-frame disagreement of their steps with
// the fusion's verdicts (frames.jsonl "odometry", read generically); the learnt calibration; the share on the
// wheels alone. One line when the run had no odometry.
void addOdometrySection(HtmlPage& page, const RunData& run);
// The navigation map (map.pgm in map_server's colours) with the run's path, start and end, metres on the axes.
// One line when the run wrote no grid.
void addNavMapSection(HtmlPage& page, const RunData& run);
// The grid of `run` with its path as an <svg> (run.grid must be set); with `other`, both runs' paths on it (each
// in its own map frame when it has one).
std::string navMapFigure(const RunData& run, const RunData* other);
// Every value of summary.json, each cell tagged with its flattened key (data-key="ate.rmse_m").
void addSummarySection(HtmlPage& page, const RunData& run);
// The unit a summary.json or frames.jsonl key names by its suffix ("computation_ms_per_frame" -> "ms/frame"); ""
// when none. `stem`, when given, gets the key without that suffix.
std::string unitOfKey(const std::string& key, std::string* stem = nullptr);
// Side by side: maps with a difference image, trajectories, ITE and headline numbers of runs a and b.
void addComparisonSection(HtmlPage& page, const RunData& a, const RunData& b);

}  // namespace sb::report
