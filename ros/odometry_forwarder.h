#pragma once
// The robot's wheel odometry into slamboosterd (issue 41's live ROS door): subscribes ~odom_topic
// (nav_msgs/Odometry, default /odom), looks the camera mount up once with tf2 (the messages' child frame, the
// base, to ~odom_camera_frame, the depth camera's optical frame), and pushes each sample, T_camera_to_odom
// stamped with the message's header stamp, to the daemon's socket with ?ODOM (client/odometry_pusher.h).
// Samples that arrive before the mount is known are skipped (counted); a daemon restart is survived by
// reconnecting on the next sample. Once a second it publishes its counts on /diagnostics (status
// `slambooster: odometry in`: pushed, skipped, failed, the newest stamp the daemon took), so that a robot's
// operator, and the tests, can see that the wheels reach the daemon.

#include <nav_msgs/Odometry.h>
#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <ros/subscriber.h>
#include <ros/wall_timer.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <Eigen/Geometry>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "client/connection.h"
#include "ros/bridge_config.h"

namespace sb::ros_bridge {

class OdometryForwarder {
 public:
  OdometryForwarder(ros::NodeHandle& node, const BridgeConfig& config);

 private:
  void onOdometry(const nav_msgs::Odometry::ConstPtr& message);
  void publishDiagnostics();

  const BridgeConfig& config_;
  tf2_ros::Buffer buffer_;
  tf2_ros::TransformListener listener_;
  ros::Subscriber odometry_;
  ros::Publisher diagnostics_;
  ros::WallTimer diagnosticsTimer_;
  std::mutex mutex_;
  std::optional<Eigen::Isometry3d> mount_;  // the camera's optical frame in the base frame
  std::unique_ptr<client::Connection> connection_;
  uint64_t pushed_ = 0, skipped_ = 0, failed_ = 0;  // samples the daemon took, without a mount, refused or unsent
  std::optional<double> newestPushed_;             // the newest stamp the daemon took, seconds
  std::string lastError_;                          // why the last sample was skipped or not taken
};

}  // namespace sb::ros_bridge
