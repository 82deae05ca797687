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
// Every value of summary.json, each cell tagged with its flattened key (data-key="ate.rmse_m").
void addSummarySection(HtmlPage& page, const RunData& run);
// Side by side: maps with a difference image, trajectories, ITE and headline numbers of runs a and b.
void addComparisonSection(HtmlPage& page, const RunData& a, const RunData& b);

}  // namespace sb::report
