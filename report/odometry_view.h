#pragma once
// The wheels against the view, prepared for plotting (report_odometry.cpp): the wheels' poses at the frames'
// stamps, their path in the estimate's frame, the per-frame disagreement between the wheels' step and the
// run's, and the verdict lanes read generically from frames.jsonl's "odometry" objects.

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "report/plots.h"
#include "report/run_data.h"

namespace sb::report {

// The wheels' pose (T_camera_to_odom) at `t`: interpolated between the two samples around it (position
// linearly, rotation by slerp); nullopt outside the samples' span or inside a gap longer than `maxGapS`.
std::optional<Eigen::Isometry3d> wheelsAt(const Trajectory& wheels, double t, double maxGapS = 0.5);

struct WheelsAgainstRun {
  std::vector<double> frame;               // frames with a pose of their own and of the previous frame, both ends
  std::vector<double> translationCm;       // |wheels' step - run's step|, cm (the steps in the previous camera's frame)
  std::vector<double> rotationDeg;         // angle of the rotation between the two steps, degrees
  std::vector<double> wheelsStepCm;        // the wheels' step length, cm (0 when the wheels stood still)
  std::vector<Eigen::Vector3d> wheelsPath; // the wheels' camera positions at the frames' stamps in the run's world
                                           // frame (anchored at the first frame both have), NaN where they have none
  double wheelsOnlyM = 0;                  // metres the wheels drove on frames whose state was odometry
  size_t wheelsOnlyFrames = 0;             // frames whose state was odometry (dead reckoning)
};

// From frames.jsonl's per-frame poses (every frame, lost ones held) and `run.wheels`.
WheelsAgainstRun compareWheels(const RunData& run);

// One lane per verdict in frames.jsonl's "odometry": each boolean field true ("used", "rejected", any new one),
// "available" false as "no wheels' pose", the tracking state odometry as "dead reckoning", and each value of
// every text field other than "why" ("fault: slipping"). Lanes with no frame are left out.
std::vector<EventMarks> odometryVerdictLanes(const FrameLog& log);

// frames.jsonl "odometry" fields that are numbers (not booleans): one series each over the frame index.
std::vector<Series> odometryNumberSeries(const FrameLog& log);

// The reasons in "why", grouped with their digits masked: (example text, frames, first frame, last frame),
// most frequent first.
struct ReasonCount {
  std::string example;
  size_t frames = 0;
  double first = 0, last = 0;
};
std::vector<ReasonCount> odometryReasons(const FrameLog& log, size_t maxReasons = 8);

}  // namespace sb::report
