#include "report/trajectory_view.h"

#include <algorithm>

namespace sb::report {

namespace {

const char* kAxisNames[3] = {"x", "y", "z"};

}  // namespace

TopView chooseTopView(const RunData& run) {
  const Trajectory& t = run.groundTruth.empty() ? run.trajectory : run.groundTruth;
  TopView v;
  if (!t.empty()) {
    Eigen::Vector3d lo = t.front().position(), hi = lo;
    for (const auto& p : t) {
      lo = lo.cwiseMin(p.position());
      hi = hi.cwiseMax(p.position());
    }
    const Eigen::Vector3d extent = hi - lo;
    int drop = 0;
    for (int i = 1; i < 3; ++i)
      if (extent[i] < extent[drop]) drop = i;
    v.axisX = drop == 0 ? 1 : 0;
    v.axisY = drop == 2 ? 1 : 2;
  }
  v.xLabel = std::string(kAxisNames[v.axisX]) + " (m)";
  v.yLabel = std::string(kAxisNames[v.axisY]) + " (m)";
  v.dropped = kAxisNames[3 - v.axisX - v.axisY];
  return v;
}

Series estimateSeries(const RunData& run, const TopView& view, const std::string& name) {
  Series s;
  s.name = name;
  for (const auto& p : run.trajectory) {
    const Eigen::Vector3d q = run.ate ? Eigen::Vector3d(run.ate->alignment * p.position()) : p.position();
    s.x.push_back(q[view.axisX]);
    s.y.push_back(q[view.axisY]);
  }
  return s;
}

Series groundTruthSeries(const RunData& run, const TopView& view) {
  Series s;
  s.name = "ground truth";
  s.color = "#555555";
  s.dashed = true;
  s.width = 1.5;
  for (const auto& p : run.groundTruth) {
    s.x.push_back(p.position()[view.axisX]);
    s.y.push_back(p.position()[view.axisY]);
  }
  return s;
}

Series iteSeries(const RunData& run, bool unaligned, const std::string& name) {
  Series s;
  s.name = name;
  if (!run.ate) return s;
  const auto& errors = unaligned ? run.ate->unalignedErrors : run.ate->errors;
  for (size_t k = 0; k < run.ate->timestamps.size() && k < errors.size(); ++k) {
    // Matches carry the estimate's timestamps; the pose's index in trajectory.tum is its frame.
    const auto it = std::lower_bound(run.trajectory.begin(), run.trajectory.end(), run.ate->timestamps[k],
                                     [](const TimedPose& p, double t) { return p.timestamp < t; });
    const size_t index = static_cast<size_t>(it - run.trajectory.begin());
    const double frame = index < run.frames.size() ? run.frames.frame[index] : static_cast<double>(index);
    s.x.push_back(frame);
    s.y.push_back(errors[k] * 100.0);
  }
  return s;
}

}  // namespace sb::report
