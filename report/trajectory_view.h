#pragma once
// Trajectories prepared for plotting: the estimate mapped into the ground truth's frame (when an alignment
// exists), projected on the plane of the two axes with the largest extent (the "top view" for handheld and
// robot motion), and per-frame errors indexed by frame.

#include <string>
#include <vector>

#include "report/plots.h"
#include "report/run_data.h"

namespace sb::report {

struct TopView {
  int axisX = 0, axisY = 2;  // indices into (x, y, z)
  std::string xLabel, yLabel, dropped;  // "x (m)", "z (m)", "y"
};

// Chooses the view from the ground truth when present, else from the estimate.
TopView chooseTopView(const RunData& run);

// The estimate in the ground-truth frame (aligned) or in the volume frame, projected on `view`.
Series estimateSeries(const RunData& run, const TopView& view, const std::string& name);
Series groundTruthSeries(const RunData& run, const TopView& view);

// Aligned and unaligned per-frame error (cm) over the frame index of the matched estimate poses.
Series iteSeries(const RunData& run, bool unaligned, const std::string& name);

}  // namespace sb::report
