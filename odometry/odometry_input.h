#pragma once
// Which odometry a run is given (issue 41's first door and the choice behind the others): the robot's
// odometry as one stream (odometry/odometry_track.h) from a sequence's odometry.txt, another file, a bag's
// nav_msgs/Odometry topic, or none. `slambooster run` (--odometry, --no-odometry) and the daemon's replay
// (source.odometry) choose through it; the daemon's socket and the ROS bridge add samples to a live track.
//
//   OdometryInput in = openOdometry("auto", "seq/");   // seq/odometry.txt when present
//   if (in.track) run.runner().setOdometry(in.track);  header.odometry = in.summary();

#include <memory>
#include <optional>
#include <string>

#include "odometry/odometry_track.h"
#include "odometry/motion_model.h"
#include "report/run_summary.h"

namespace sb {

inline constexpr const char* kOdometryFileName = "odometry.txt";  // beside depth.txt

struct OdometryInput {
  std::shared_ptr<odometry::OdometryTrack> track;  // nullptr: none
  std::string source;                              // where it came from ("" with none)
  // The summary's "odometry" object at the start (nullopt with none).
  std::optional<OdometrySummary> summary() const;
};

// Options of a bag's odometry (drivers/bag_plugin.h).
struct BagOdometryOptions {
  std::string topic;        // nav_msgs/Odometry topic; empty: the bag's only one
  std::string cameraMount;  // "x y z qx qy qz qw" of the camera's optical frame in the base frame; empty: /tf_static
};

// `choice`: "none" (no odometry), "auto" (SEQUENCE/odometry.txt when SEQUENCE is a directory holding one, a
// bag's only nav_msgs/Odometry topic when SEQUENCE is a .bag that has one; else none) or the path of a TUM-format
// odometry.txt. Throws sb::Error naming the file and line (or the bag and topic) on bad input.
OdometryInput openOdometry(const std::string& choice, const std::string& sequence,
                           const BagOdometryOptions& bag = {});

// A fresh, empty track whose samples arrive while the run goes on (the daemon's socket, the ROS bridge).
OdometryInput liveOdometry(const std::string& source);

// Updates `summary` for a frame at `timestamp` (before the frame is stepped): the track's sample count, the
// frames the odometry covered and the odometry camera's path over them. `last`: the previous covered frame's
// odometry pose (updated).
void countOdometryFrame(const odometry::OdometryTrack& track, double timestamp, OdometrySummary& summary,
                        std::optional<Eigen::Isometry3d>& last);

// The wheels' errors, the mount's and the odometry's clock learnt so far, into the summary.
void noteCalibration(const odometry::MotionModel& model, OdometrySummary& summary);

}  // namespace sb
