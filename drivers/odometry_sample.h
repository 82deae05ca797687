#pragma once
// One sample of the robot's odometry as a driver delivers it (a sequence's odometry.txt, a bag's
// nav_msgs/Odometry, the socket's ?ODOM, the ROS bridge's ~odom_topic): a stamped camera pose in the odometry
// frame. The stream of them, its interpolation and its fusion with the view are the odometry module's
// (odometry/odometry_track.h, docs/odometry.md).
//
// T_camera_to_odom is the camera's pose in the odometry frame (the base's odometry composed with the camera
// mount), the camera in the optical convention of groundtruth.txt (x right, y down, z forward); the odometry
// frame is the base's (ROS REP 103: x forward, y left, z up). Stamps are seconds on the depth frames' clock.

#include <Eigen/Geometry>
#include <optional>

namespace sb::odometry {

using Matrix6 = Eigen::Matrix<double, 6, 6>;

struct OdometrySample {
  double timestamp = 0.0;  // seconds, on the depth frames' clock
  Eigen::Isometry3d T_camera_to_odom = Eigen::Isometry3d::Identity();
  // Of the pose, in the odometry frame, order tx ty tz rx ry rz (m^2, rad^2), when the source states one.
  std::optional<Matrix6> covariance;
};

}  // namespace sb::odometry
