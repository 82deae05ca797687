#pragma once
// Depth from ROS topics into slamboosterd: subscribes to a sensor_msgs/Image depth topic (16UC1 mm or 32FC1
// m) and its sensor_msgs/CameraInfo, converts each frame with the same code as the bag plugin, and pushes it
// to the daemon's push source (source.type "push") stamped with the image's header stamp. Frames that arrive
// before the first CameraInfo are skipped (counted); a daemon restart is survived by reconnecting on the next
// frame.

#include <ros/node_handle.h>
#include <ros/subscriber.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <memory>
#include <mutex>
#include <optional>

#include "client/frame_pusher.h"
#include "core/intrinsics.h"
#include "ros/bridge_config.h"

namespace sb::ros_bridge {

class DepthForwarder {
 public:
  DepthForwarder(ros::NodeHandle& node, const BridgeConfig& config);

 private:
  void onCameraInfo(const sensor_msgs::CameraInfo::ConstPtr& info);
  void onDepth(const sensor_msgs::Image::ConstPtr& image);

  const BridgeConfig& config_;
  ros::Subscriber depth_;
  ros::Subscriber cameraInfo_;
  std::mutex mutex_;  // the callbacks may run on different spinner threads
  std::optional<Intrinsics> intrinsics_;
  std::unique_ptr<client::FramePusher> pusher_;
  uint64_t pushed_ = 0;
  uint64_t skipped_ = 0;
};

}  // namespace sb::ros_bridge
