// slambooster_ros: the ROS 1 bridge of slamboosterd (README "With ROS"). A client of the daemon's socket that
// publishes odometry, TF, tracking state and diagnostics; with ~push_socket set it also hands depth frames
// from a ROS topic to the daemon's push source. The daemon itself never links ROS.

#include <ros/ros.h>

#include <memory>

#include "core/error.h"
#include "ros/cloud_publisher.h"
#include "ros/daemon_link.h"
#include "ros/depth_forwarder.h"
#include "ros/grid_publisher.h"
#include "ros/odometry_forwarder.h"
#include "ros/master_watch.h"
#include "ros/odometry_publisher.h"
#include "ros/ros_params.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "slambooster");
  ros::NodeHandle node;
  ros::NodeHandle privateNode("~");
  sb::ros_bridge::BridgeConfig config;
  try {
    config = sb::ros_bridge::readBridgeConfig(privateNode);
  } catch (const sb::Error& e) {
    ROS_FATAL("%s", e.what());
    return 2;
  }
  // Depth subscriptions are served by their own spinner thread, so that waiting on the daemon's socket never
  // delays a depth frame.
  std::unique_ptr<sb::ros_bridge::DepthForwarder> forwarder;
  if (!config.pushSocket.empty()) forwarder = std::make_unique<sb::ros_bridge::DepthForwarder>(node, config);
  std::unique_ptr<sb::ros_bridge::OdometryForwarder> wheels;  // the robot's odometry to the daemon (?ODOM)
  if (!config.odomTopic.empty()) wheels = std::make_unique<sb::ros_bridge::OdometryForwarder>(node, config);
  ros::AsyncSpinner spinner(1);
  spinner.start();
  const sb::ros_bridge::MasterWatch watch;  // a restarted master ends the bridge with status 3
  sb::ros_bridge::OdometryPublisher publisher(node, privateNode, config, wheels.get());
  sb::ros_bridge::GridPublisher grid(privateNode, config);    // ~map, its TF, ~octomap (issue 45)
  sb::ros_bridge::CloudPublisher cloud(privateNode, config);  // ~cloud
  sb::ros_bridge::DaemonLink(config, publisher, &grid, &cloud).run();
  spinner.stop();
  return 0;
}
