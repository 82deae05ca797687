#pragma once
// The robot's wheel odometry into slamboosterd (issue 41's live ROS door): subscribes ~odom_topic
// (nav_msgs/Odometry, default /odom), looks the camera mount up once with tf2 (the messages' child frame, the
// base, to ~odom_camera_frame, the depth camera's optical frame), and pushes each sample, T_camera_to_odom
// stamped with the message's header stamp, to the daemon's socket with ?ODOM (client/odometry_pusher.h).
// Samples that arrive before the mount is known are skipped (counted); a daemon restart is survived by
// reconnecting on the next sample. Once a second it publishes its counts on /diagnostics (status
// `slambooster: odometry in`: pushed, skipped, failed, the newest stamp the daemon took), so that a robot's
// operator, and the tests, can see that the wheels reach the daemon.
// It also tells the publisher the robot's frames (issue 57): the odometry's frame (`odom`), its child (the
// base) and the mount, once known, and the camera in odom at a frame's stamp from TF (odom -> base, as the
// base publishes it, composed with the mount), from which map -> odom is computed.

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

// The robot's frames as its odometry names them.
struct RobotFrames {
  std::string odomFrame;     // the odometry's header.frame_id (REP 105's `odom`)
  std::string baseFrame;     // its child_frame_id (`base_link`, `base_footprint`)
  Eigen::Isometry3d cameraInBase = Eigen::Isometry3d::Identity();  // the mount, as pushed to the daemon
};

class OdometryForwarder {
 public:
  OdometryForwarder(ros::NodeHandle& node, const BridgeConfig& config);

  // Known once a sample arrived with its mount in TF; nullopt before (then the bridge keeps map -> camera).
  std::optional<RobotFrames> robotFrames() const;
  // The camera in odom at `stamp`: TF's odom -> base there (waiting up to `waitSeconds` for it to arrive)
  // composed with the mount. nullopt with `why` set when TF does not have it.
  std::optional<Eigen::Isometry3d> cameraInOdom(const RobotFrames& frames, const ros::Time& stamp,
                                                double waitSeconds, std::string& why) const;
  // The parent `frame` has in TF now (published by another node), or nullopt when TF does not know it.
  std::optional<std::string> parentInTf(const std::string& frame) const;

 private:
  void onOdometry(const nav_msgs::Odometry::ConstPtr& message);
  void publishDiagnostics();

  const BridgeConfig& config_;
  tf2_ros::Buffer buffer_;
  tf2_ros::TransformListener listener_;
  ros::Subscriber odometry_;
  ros::Publisher diagnostics_;
  ros::WallTimer diagnosticsTimer_;
  mutable std::mutex mutex_;
  std::optional<Eigen::Isometry3d> mount_;  // the camera's optical frame in the base frame
  std::string odomFrame_, baseFrame_;       // of the sample the mount was looked up for
  std::unique_ptr<client::Connection> connection_;
  uint64_t pushed_ = 0, skipped_ = 0, failed_ = 0;  // samples the daemon took, without a mount, refused or unsent
  std::optional<double> newestPushed_;             // the newest stamp the daemon took, seconds
  std::string lastError_;                          // why the last sample was skipped or not taken
};

}  // namespace sb::ros_bridge
