#pragma once
// REP 105's `map` -> `odom` (issue 57): the correction that makes map -> odom -> base_link, with the robot's
// own odometry as odom -> base_link, equal the daemon's pose. Per frame, at the frame's stamp:
//   map_T_odom = map_T_camera * inverse(odom_T_camera),   odom_T_camera = odom_T_base(stamp) * base_T_camera.
// A jump of the daemon's pose (a relocalisation, a correction) goes into map -> odom only; odom -> base_link
// stays the base's, continuous. On a lost frame the daemon's pose says nothing about now, so the last
// map -> odom is held and the robot keeps moving on its odometry. No ROS here: tested without a master.

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>

#include "ros/daemon_reports.h"

namespace sb::ros_bridge {

// The daemon's pose of a frame (POSE's position and quaternion): the camera's optical frame in map.
Eigen::Isometry3d cameraInMap(const PoseReport& pose);

// Why a frame's map -> odom is the last one rather than its own.
enum class MapOdomHold {
  none,        // computed from this frame
  lost,        // the frame is lost: its pose is the held one, not a measurement
  noOdometry,  // the robot's odometry at the frame's stamp is unknown (not in TF yet, or no path odom ->
               // base)
};

struct MapOdomStep {
  Eigen::Isometry3d mapToOdom = Eigen::Isometry3d::Identity();
  MapOdomHold hold = MapOdomHold::none;
  uint64_t sinceFrame = 0;  // the frame the published map -> odom was computed from
};

class MapToOdom {
 public:
  // One frame: its number and state, the daemon's camera in map, and the camera in odom at the frame's stamp
  // (nullopt: unknown). Returns the map -> odom to publish for it: its own, or the last one held; nullopt
  // while there has been none (then nothing is published: the tree has no map yet).
  std::optional<MapOdomStep> onFrame(uint64_t frame, TrackingState state,
                                     const Eigen::Isometry3d& cameraInMap,
                                     const std::optional<Eigen::Isometry3d>& cameraInOdom);

 private:
  std::optional<MapOdomStep> last_;
};

// For diagnostics: "updated", "held since frame N: lost", "held since frame N: no odometry at the stamp".
std::string describe(const MapOdomStep& step);

// The stamp (nanoseconds) of a frame's forward-dated map -> odom: `toleranceS` and kForwardOffsetNs after the
// frame's. tf2 ignores a second transform at a stamp it holds, so this must never be a later frame's own
// stamp: on a regular clock stamp + tolerance often is (30 Hz and 0.1 s: frame k + 3), give or take the
// nanosecond that converting seconds to a ROS stamp loses (rospy truncates: 0.533333 s is 533332999 ns,
// 0.633333 s is 633333000 ns). One microsecond is beyond that rounding and nothing to a lookup.
inline constexpr int64_t kForwardOffsetNs = 1000;
int64_t forwardStampNs(int64_t frameStampNs, double toleranceS);

}  // namespace sb::ros_bridge
