#include "ros/grid_publisher.h"

#include <nav_msgs/OccupancyGrid.h>

#include <nlohmann/json.hpp>

#include "core/error.h"

namespace sb::ros_bridge {

GridPublisher::GridPublisher(ros::NodeHandle& privateNode, const BridgeConfig& config) : config_(config) {
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
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("MAP: malformed: ") + e.what());
  }
}

}  // namespace sb::ros_bridge
