#include "core/trajectory.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/input_file.h"

namespace sb {

Trajectory readTumTrajectory(const std::string& path) {
  InputFile in(path, "trajectory");
  Trajectory out;
  std::string line;
  int lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream ss(line);
    double t, tx, ty, tz, qx, qy, qz, qw;
    if (!(ss >> t >> tx >> ty >> tz >> qx >> qy >> qz >> qw)) {
      throw Error(path + ":" + std::to_string(lineNo) +
                  ": expected 8 numbers 'timestamp tx ty tz qx qy qz qw', got '" + line + "'");
    }
    Eigen::Quaterniond q(qw, qx, qy, qz);
    const double n = q.norm();
    if (!std::isfinite(n) || std::abs(n - 1.0) > 1e-3) {
      throw Error(path + ":" + std::to_string(lineNo) + ": quaternion norm " + std::to_string(n) +
                  " is not 1 (TUM order is qx qy qz qw)");
    }
    if (!out.empty() && t <= out.back().timestamp) {
      throw Error(path + ":" + std::to_string(lineNo) + ": timestamp " + std::to_string(t) +
                  " does not increase (previous " + std::to_string(out.back().timestamp) + ")");
    }
    TimedPose p;
    p.timestamp = t;
    p.T_camera_to_world.linear() = q.normalized().toRotationMatrix();
    p.T_camera_to_world.translation() = Eigen::Vector3d(tx, ty, tz);
    out.push_back(p);
  }
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
