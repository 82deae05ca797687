#pragma once
// A run's frames held against the truth, for the system tests that judge `slambooster run` as a user runs it:
// frames.jsonl's poses and the sequence's truth (groundtruth.txt, TUM format: sb::readTumTrajectory) both
// anchored at the first frame, by its whole pose (position and rotation), as a robot's map frame is: no
// alignment fitted. Anchored by its position alone, a drive whose first camera is pitched 2.5 degrees (seed 47)
// read 0.3 m off at 7 m where scripts/pose_honesty.py (and the truth) had 2 cm.

#include <Eigen/Core>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/trajectory.h"

namespace sb::test {

struct AnchoredFrame {
  size_t frame = 0;        // frames.jsonl "frame": the index into the truth
  double timestamp = 0.0;  // seconds, "timestamp"
  std::string state;       // "state": good, weak, lost, relocalised, odometry
  double errorM = 0.0;     // metres from the anchored estimate's position to the truth's
  Eigen::Vector3d error = Eigen::Vector3d::Zero();  // that error as a vector in the truth's world frame
  nlohmann::json line;     // the whole frames.jsonl line, for what else a test reads ("odometry", "inliers")
};

// The frames of `run`/frames.jsonl in file order, against `truth`: the estimate's first frame (frame 0 of a
// whole run) placed on the truth's pose of that frame. Throws std::runtime_error naming the file when it cannot
// be read, and the file and line when a frame has no pose in the truth.
std::vector<AnchoredFrame> anchoredFrames(const std::string& run, const sb::Trajectory& truth);

}  // namespace sb::test
