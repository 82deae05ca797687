#pragma once
// ~map of slambooster_ros (issue 45): the daemon's navigation grid (its MAP reply to ?MAP, docs/protocol.md)
// as a latched nav_msgs/OccupancyGrid in ~grid_frame (the map frame: z up, z = 0 the floor), renewed every
// ~map_period_s. The bridge never rebuilds the grid: it decodes the daemon's. From a daemon of protocol 1.7
// also the grid frame's place: ~map_frame -> ~grid_frame on /tf_static (with ~publish_tf; sent again only when
// it changes, e.g. a new pass), and map.bt's path as the parameter ~octomap (Debian 12 has no octomap_msgs).

#include <ros/ros.h>

#include <tf2_ros/static_transform_broadcaster.h>

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "ros/bridge_config.h"

namespace sb::ros_bridge {

class GridPublisher {
 public:
  GridPublisher(ros::NodeHandle& privateNode, const BridgeConfig& config);
  // A MAP message; throws sb::Error naming the member when it is malformed.
  void onMap(const nlohmann::json& map);
  size_t published() const { return published_; }

 private:
  void onFrame(const nlohmann::json& frameInWorld);

  const BridgeConfig& config_;
  ros::NodeHandle& privateNode_;
  ros::Publisher grid_;
  tf2_ros::StaticTransformBroadcaster staticTf_;
  std::vector<double> lastFrame_;  // the last frame_in_world sent (position, quaternion)
  std::string lastOctomap_;
  size_t published_ = 0;
};

}  // namespace sb::ros_bridge
