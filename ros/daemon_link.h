#pragma once
// The bridge's side of slamboosterd's socket: connect, watch, hand each report to the publisher, and when the
// daemon goes away (restart, crash, not started yet) keep trying until ROS shuts down.

#include <string>

#include "ros/bridge_config.h"
#include "ros/cloud_publisher.h"
#include "ros/grid_publisher.h"
#include "ros/odometry_publisher.h"

namespace sb::ros_bridge {

class DaemonLink {
 public:
  DaemonLink(const BridgeConfig& config, OdometryPublisher& publisher, GridPublisher* grid = nullptr,
             CloudPublisher* cloud = nullptr);
  // Runs until ros::ok() turns false.
  void run();

 private:
  // One connection's life; returns why it ended.
  std::string serveOnce();

  const BridgeConfig& config_;
  OdometryPublisher& publisher_;
  GridPublisher* grid_;  // ~map, or nullptr
  CloudPublisher* cloud_;  // ~cloud, or nullptr
  bool announcedDown_ = false;  // "disconnected" was published since the last connection
};

}  // namespace sb::ros_bridge
