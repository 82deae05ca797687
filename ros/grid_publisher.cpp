#include "ros/grid_publisher.h"

#include <nav_msgs/OccupancyGrid.h>

#include <nlohmann/json.hpp>

#include "core/error.h"

namespace sb::ros_bridge {

GridPublisher::GridPublisher(ros::NodeHandle& privateNode, const BridgeConfig& config)
    : config_(config), privateNode_(privateNode) {
  grid_ = privateNode.advertise<nav_msgs::OccupancyGrid>("map", 1, /*latch=*/true);
}

void GridPublisher::onMap(const nlohmann::json& j) {
  try {
    nav_msgs::OccupancyGrid grid;
    grid.header.stamp = ros::Time::now();
    grid.header.frame_id = config_.gridFrame;
    grid.info.map_load_time = grid.header.stamp;
    grid.info.resolution = j.at("resolution").get<float>();
    grid.info.width = j.at("width").get<uint32_t>();
    grid.info.height = j.at("height").get<uint32_t>();
    grid.info.origin.position.x = j.at("origin").at(0).get<double>();
    grid.info.origin.position.y = j.at("origin").at(1).get<double>();
    grid.info.origin.orientation.w = 1.0;
    const nlohmann::json& runs = j.at("runs");
    grid.data.reserve(size_t(grid.info.width) * grid.info.height);
    for (size_t i = 0; i + 1 < runs.size(); i += 2)
      grid.data.insert(grid.data.end(), runs[i + 1].get<size_t>(), runs[i].get<int8_t>());
    if (grid.data.size() != size_t(grid.info.width) * grid.info.height)
      throw Error("MAP: its runs hold " + std::to_string(grid.data.size()) + " cells, not width x height");
    grid_.publish(grid);
    ++published_;
    if (j.contains("frame_in_world") && config_.publishTf) onFrame(j.at("frame_in_world"));
    if (j.contains("octomap") && j.at("octomap").get<std::string>() != lastOctomap_) {
      lastOctomap_ = j.at("octomap").get<std::string>();
      privateNode_.setParam("octomap", lastOctomap_);
    }
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("MAP: malformed: ") + e.what());
  }
}

void GridPublisher::onFrame(const nlohmann::json& f) {
  std::vector<double> v = f.at("position").get<std::vector<double>>();
  const std::vector<double> q = f.at("quaternion").get<std::vector<double>>();
  if (v.size() != 3 || q.size() != 4) throw Error("MAP: frame_in_world needs 3 position and 4 quaternion numbers");
  v.insert(v.end(), q.begin(), q.end());
  if (v == lastFrame_) return;  // static: once per change
  lastFrame_ = v;
  geometry_msgs::TransformStamped t;
  t.header.stamp = ros::Time::now();
  t.header.frame_id = config_.mapFrame;
  t.child_frame_id = config_.gridFrame;
  t.transform.translation.x = v[0];
  t.transform.translation.y = v[1];
  t.transform.translation.z = v[2];
  t.transform.rotation.x = v[3];
  t.transform.rotation.y = v[4];
  t.transform.rotation.z = v[5];
  t.transform.rotation.w = v[6];
  staticTf_.sendTransform(t);
}

}  // namespace sb::ros_bridge
