#include "core/trajectory.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/input_file.h"

namespace sb {

TumTrajectoryReader::TumTrajectoryReader(const std::string& path) : path_(path), in_(std::make_unique<InputFile>(path, "trajectory")) {}

TumTrajectoryReader::~TumTrajectoryReader() = default;

bool TumTrajectoryReader::next(TimedPose& pose) {
  while (std::getline(*in_, line_)) {
    ++lineNo_;
    const auto first = line_.find_first_not_of(" \t\r");
    if (first == std::string::npos || line_[first] == '#') continue;
    std::istringstream ss(line_);
    double t, tx, ty, tz, qx, qy, qz, qw;
    if (!(ss >> t >> tx >> ty >> tz >> qx >> qy >> qz >> qw)) {
      throw Error(path_ + ":" + std::to_string(lineNo_) +
                  ": expected 8 numbers 'timestamp tx ty tz qx qy qz qw', got '" + line_ + "'");
    }
    Eigen::Quaterniond q(qw, qx, qy, qz);
    const double n = q.norm();
    if (!std::isfinite(n) || std::abs(n - 1.0) > 1e-3) {
      throw Error(path_ + ":" + std::to_string(lineNo_) + ": quaternion norm " + std::to_string(n) +
                  " is not 1 (TUM order is qx qy qz qw)");
    }
    if (any_ && t <= previous_) {
      throw Error(path_ + ":" + std::to_string(lineNo_) + ": timestamp " + std::to_string(t) +
                  " does not increase (previous " + std::to_string(previous_) + ")");
    }
    any_ = true;
    previous_ = t;
    pose = TimedPose{};
    pose.timestamp = t;
    pose.T_camera_to_world.linear() = q.normalized().toRotationMatrix();
    pose.T_camera_to_world.translation() = Eigen::Vector3d(tx, ty, tz);
    return true;
  }
  if (in_->bad()) throw Error(path_ + ": reading failed after line " + std::to_string(lineNo_));
  return false;
}

Trajectory readTumTrajectory(const std::string& path) {
  TumTrajectoryReader reader(path);
  Trajectory out;
  TimedPose p;
  while (reader.next(p)) out.push_back(p);
  return out;
}

std::string formatTumLine(const TimedPose& pose) {
  const Eigen::Quaterniond q(pose.T_camera_to_world.rotation());
  const Eigen::Vector3d t = pose.T_camera_to_world.translation();
  char buf[256];
  std::snprintf(buf, sizeof buf, "%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f", pose.timestamp, t.x(), t.y(), t.z(),
                q.x(), q.y(), q.z(), q.w());
  return buf;
}

void writeTumTrajectory(const std::string& path, const Trajectory& trajectory, const std::string& comment) {
  std::ofstream out(path);
  if (!out) throw Error("cannot write trajectory '" + path + "': check that the directory exists");
  out << "# timestamp tx ty tz qx qy qz qw (camera-to-world, metres)\n";
  if (!comment.empty()) out << "# " << comment << "\n";
  for (const auto& p : trajectory) out << formatTumLine(p) << "\n";
  if (!out) throw Error("writing trajectory '" + path + "' failed (disk full?)");
}

}  // namespace sb
