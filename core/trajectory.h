#pragma once
// Camera trajectories in TUM format: one line per pose, `timestamp tx ty tz qx qy qz qw`, camera-to-world,
// metres and seconds. Lines starting with '#' are comments.

#include <Eigen/Geometry>
#include <istream>
#include <memory>
#include <string>
#include <vector>

namespace sb {

struct TimedPose {
  double timestamp = 0.0;                                 // seconds
  Eigen::Isometry3d T_camera_to_world = Eigen::Isometry3d::Identity();

  Eigen::Vector3d position() const { return T_camera_to_world.translation(); }
};

using Trajectory = std::vector<TimedPose>;

// Reads a TUM trajectory. Throws sb::Error naming the file and line on malformed input, a non-unit
// quaternion (|q| off by more than 1e-3; it is normalised otherwise) or non-increasing timestamps.
Trajectory readTumTrajectory(const std::string& path);

// The same reader one pose at a time, for files too long to hold (a day's odometry.txt): the same checks, the
// same messages. Memory is one line's.
class TumTrajectoryReader {
 public:
  explicit TumTrajectoryReader(const std::string& path);  // throws sb::Error when the path is not a readable file
  ~TumTrajectoryReader();
  // The next pose; false at the end of the file. Throws sb::Error naming the file and line on bad input.
  bool next(TimedPose& pose);

 private:
  std::string path_;
  std::unique_ptr<std::istream> in_;
  std::string line_;
  int lineNo_ = 0;
  bool any_ = false;
  double previous_ = 0.0;
};

// Writes a TUM trajectory with full precision (9 decimals for positions/quaternions, 6 for timestamps),
// after the column header line and, when given, one more comment line `# <comment>`.
// Throws sb::Error if the file cannot be written.
void writeTumTrajectory(const std::string& path, const Trajectory& trajectory, const std::string& comment = "");

// One TUM line without newline, for streaming writers.
std::string formatTumLine(const TimedPose& pose);

}  // namespace sb
