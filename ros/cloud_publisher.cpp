#include "ros/cloud_publisher.h"

#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <nlohmann/json.hpp>

#include "core/error.h"

namespace sb::ros_bridge {

CloudPublisher::CloudPublisher(ros::NodeHandle& privateNode, const BridgeConfig& config) : config_(config) {
  cloud_ = privateNode.advertise<sensor_msgs::PointCloud2>("cloud", 1, /*latch=*/true);
}

void CloudPublisher::onCloud(const nlohmann::json& j) {
  try {
    const double resolution = j.at("resolution").get<double>();
    const nlohmann::json& cells = j.at("cells");
    if (!(resolution > 0.0) || cells.size() % 3 != 0)
      throw Error("CLOUD: 'resolution' must be positive and 'cells' hold index triples (" +
                  std::to_string(cells.size()) + " numbers)");
    sensor_msgs::PointCloud2 cloud;
    cloud.header.stamp = ros::Time::now();
    cloud.header.frame_id = config_.gridFrame;
    sensor_msgs::PointCloud2Modifier modifier(cloud);
    modifier.setPointCloud2FieldsByString(1, "xyz");
    modifier.resize(cells.size() / 3);
    sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
    for (size_t i = 0; i < cells.size(); i += 3, ++x, ++y, ++z) {  // a cell's centre, metres
      *x = static_cast<float>((cells[i].get<int32_t>() + 0.5) * resolution);
      *y = static_cast<float>((cells[i + 1].get<int32_t>() + 0.5) * resolution);
      *z = static_cast<float>((cells[i + 2].get<int32_t>() + 0.5) * resolution);
    }
    cloud_.publish(cloud);
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("CLOUD: malformed: ") + e.what());
  }
}

}  // namespace sb::ros_bridge
