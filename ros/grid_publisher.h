#pragma once
// ~map of slambooster_ros (issue 45): the daemon's navigation grid (its MAP reply to ?MAP, docs/protocol.md)
// as a latched nav_msgs/OccupancyGrid in ~grid_frame (the map frame: z up, z = 0 the floor), renewed every
// ~map_period_s. The bridge never rebuilds the grid: it decodes the daemon's.

#include <ros/ros.h>

#include <nlohmann/json_fwd.hpp>

#include "ros/bridge_config.h"

namespace sb::ros_bridge {

class GridPublisher {
 public:
  GridPublisher(ros::NodeHandle& privateNode, const BridgeConfig& config);
  // A MAP message; throws sb::Error naming the member when it is malformed.
  void onMap(const nlohmann::json& map);
  size_t published() const { return published_; }

 private:
  const BridgeConfig& config_;
  ros::Publisher grid_;
  size_t published_ = 0;
};

}  // namespace sb::ros_bridge
