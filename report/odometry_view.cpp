#include "report/odometry_view.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>

#include "core/tracking_state.h"

namespace sb::report {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::optional<Eigen::Isometry3d> framePose(const FrameLog& log, size_t i) {
  if (i >= log.pose.size()) return std::nullopt;
  const auto& p = log.pose[i];
  for (double v : p)
    if (!std::isfinite(v)) return std::nullopt;
  const Eigen::Quaterniond q(p[6], p[3], p[4], p[5]);
  if (q.norm() < 0.5) return std::nullopt;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
  return T;
}

bool isDeadReckoning(const FrameLog& log, size_t i) {
  return i < log.state.size() && log.state[i] == static_cast<double>(TrackingState::odometry);
}

}  // namespace

std::optional<Eigen::Isometry3d> wheelsAt(const Trajectory& wheels, double t, double maxGapS) {
  if (wheels.empty() || !std::isfinite(t) || t < wheels.front().timestamp || t > wheels.back().timestamp)
    return std::nullopt;
  const auto after = std::lower_bound(wheels.begin(), wheels.end(), t,
                                      [](const TimedPose& p, double s) { return p.timestamp < s; });
  if (after->timestamp == t) return after->T_camera_to_world;
  const auto before = after - 1;
  const double gap = after->timestamp - before->timestamp;
  if (gap > maxGapS) return std::nullopt;
  const double s = (t - before->timestamp) / gap;
  const Eigen::Quaterniond qa(before->T_camera_to_world.rotation()), qb(after->T_camera_to_world.rotation());
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = qa.slerp(s, qb).toRotationMatrix();
  T.translation() = (1 - s) * before->T_camera_to_world.translation() + s * after->T_camera_to_world.translation();
  return T;
}

WheelsAgainstRun compareWheels(const RunData& run) {
  WheelsAgainstRun out;
  const FrameLog& log = run.frames;
  std::optional<Eigen::Isometry3d> anchor;  // odometry frame -> the run's world frame
  std::optional<Eigen::Isometry3d> prevRun, prevWheels;
  for (size_t i = 0; i < log.size(); ++i) {
    const std::optional<Eigen::Isometry3d> E = framePose(log, i);
    const std::optional<Eigen::Isometry3d> W = wheelsAt(run.wheels, log.timestamp[i]);
    if (E && W && !anchor) anchor = *E * W->inverse();
    out.wheelsPath.push_back(W && anchor ? Eigen::Vector3d((*anchor * *W).translation())
                                         : Eigen::Vector3d::Constant(kNaN));
    if (isDeadReckoning(log, i)) {
      ++out.wheelsOnlyFrames;
      if (W && prevWheels) out.wheelsOnlyM += (W->translation() - prevWheels->translation()).norm();
    }
    if (E && W && prevRun && prevWheels) {
      const Eigen::Isometry3d runStep = prevRun->inverse() * *E;
      const Eigen::Isometry3d wheelStep = prevWheels->inverse() * *W;
      out.frame.push_back(log.frame[i]);
      out.translationCm.push_back((wheelStep.translation() - runStep.translation()).norm() * 100.0);
      out.rotationDeg.push_back(Eigen::AngleAxisd(wheelStep.rotation().transpose() * runStep.rotation()).angle() *
                                180.0 / M_PI);
      out.wheelsStepCm.push_back(wheelStep.translation().norm() * 100.0);
    }
    prevRun = E;
    prevWheels = W;
  }
  return out;
}

std::vector<EventMarks> odometryVerdictLanes(const FrameLog& log) {
  std::vector<EventMarks> lanes;
  const auto add = [&](const std::string& name, std::vector<double> frames, const std::string& colour) {
    if (!frames.empty()) lanes.push_back({name, std::move(frames), colour, true});
  };
  // Colours for the verdicts the fusion has today; a new one takes the palette's next colour.
  static const std::map<std::string, std::string> known = {
      {"used", "#009e73"}, {"rejected", "#d55e00"}, {"fused", "#56b4e9"}};
  for (const auto& c : log.odometry) {
    if (!c.boolean) continue;
    std::vector<double> frames;
    for (size_t i = 0; i < c.values.size() && i < log.size(); ++i)
      if (c.name == "available" ? c.values[i] == 0.0 : c.values[i] == 1.0) frames.push_back(log.frame[i]);
    const auto colour = known.find(c.name);
    add(c.name == "available" ? "no wheels' pose" : c.name == "rejected" ? "rejected (slip)" : c.name, frames,
        colour == known.end() ? (c.name == "available" ? "#999999" : "") : colour->second);
  }
  std::vector<double> dead;
  for (size_t i = 0; i < log.size(); ++i)
    if (isDeadReckoning(log, i)) dead.push_back(log.frame[i]);
  add("dead reckoning (state odometry)", dead, "#cc79a7");
  for (const auto& t : log.odometryText) {
    if (t.name == "why") continue;
    std::vector<std::string> values;  // in first-seen order, at most 6 lanes per field
    for (const auto& v : t.values)
      if (!v.empty() && std::find(values.begin(), values.end(), v) == values.end() && values.size() < 6)
        values.push_back(v);
    for (const auto& value : values) {
      std::vector<double> frames;
      for (size_t i = 0; i < t.values.size() && i < log.size(); ++i)
        if (t.values[i] == value) frames.push_back(log.frame[i]);
      add(t.name + ": " + value, frames, "");
    }
  }
  return lanes;
}

std::vector<Series> odometryNumberSeries(const FrameLog& log) {
  std::vector<Series> out;
  for (const auto& c : log.odometry) {
    if (c.boolean) continue;
    Series s{c.name, {}, {}};
    for (size_t i = 0; i < c.values.size() && i < log.size(); ++i) {
      s.x.push_back(log.frame[i]);
      s.y.push_back(c.values[i]);
    }
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<ReasonCount> odometryReasons(const FrameLog& log, size_t maxReasons) {
  std::map<std::string, ReasonCount> groups;
  for (const auto& t : log.odometryText) {
    if (t.name != "why") continue;
    for (size_t i = 0; i < t.values.size() && i < log.size(); ++i) {
      if (t.values[i].empty()) continue;
      std::string key = t.values[i];
      for (char& c : key)
        if (std::isdigit(static_cast<unsigned char>(c))) c = '#';
      auto [it, fresh] = groups.try_emplace(key);
      if (fresh) it->second.example = t.values[i], it->second.first = log.frame[i];
      ++it->second.frames;
      it->second.last = log.frame[i];
    }
  }
  std::vector<ReasonCount> out;
  for (auto& [key, r] : groups) out.push_back(r);
  std::stable_sort(out.begin(), out.end(), [](const ReasonCount& a, const ReasonCount& b) { return a.frames > b.frames; });
  if (out.size() > maxReasons) out.resize(maxReasons);
  return out;
}

}  // namespace sb::report
