#pragma once
// ~cloud of slambooster_ros (issue 45): the daemon's map surface (its CLOUD reply to ?CLOUD,
// docs/protocol.md: the occupied cells of map.bt, coarsened by the daemon to a bounded count) as a latched
// sensor_msgs/PointCloud2 of the cells' centres (x, y, z float32) in ~grid_frame, renewed every
// ~cloud_period_s. A voxel-downsampled cloud for rviz; the bridge never rebuilds the map.

#include <ros/ros.h>

#include <nlohmann/json_fwd.hpp>

#include "ros/bridge_config.h"

namespace sb::ros_bridge {

class CloudPublisher {
 public:
  CloudPublisher(ros::NodeHandle& privateNode, const BridgeConfig& config);
  // A CLOUD message; throws sb::Error naming the member when it is malformed.
  void onCloud(const nlohmann::json& cloud);

 private:
  const BridgeConfig& config_;
  ros::Publisher cloud_;
};

}  // namespace sb::ros_bridge
