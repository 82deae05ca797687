#include "ros/depth_forwarder.h"

#include <ros/ros.h>

#include "core/error.h"
#include "ros/depth_image.h"

namespace sb::ros_bridge {

namespace {

// Depth messages buffered by ROS before the oldest is dropped: live input keeps the newest (the daemon's
// queue then applies the same rule and counts its drops).
constexpr uint32_t kDepthQueue = 2;
constexpr uint32_t kInfoQueue = 1;
constexpr double kWarnPeriodSeconds = 5.0;

std::string cameraInfoTopicFor(const std::string& imageTopic) {
  const auto slash = imageTopic.rfind('/');
  return (slash == std::string::npos ? std::string() : imageTopic.substr(0, slash + 1)) + "camera_info";
}

}  // namespace

DepthForwarder::DepthForwarder(ros::NodeHandle& node, const BridgeConfig& config) : config_(config) {
  const std::string infoTopic =
      config.cameraInfoTopic.empty() ? cameraInfoTopicFor(node.resolveName(config.depthTopic)) : config.cameraInfoTopic;
  // TCP_NODELAY: a depth frame must not wait for Nagle's algorithm.
  depth_ = node.subscribe(config.depthTopic, kDepthQueue, &DepthForwarder::onDepth, this,
                          ros::TransportHints().tcpNoDelay());
  cameraInfo_ = node.subscribe(infoTopic, kInfoQueue, &DepthForwarder::onCameraInfo, this);
  ROS_INFO("forwarding depth from %s (+ %s) to %s", depth_.getTopic().c_str(), infoTopic.c_str(),
           config.pushSocket.c_str());
}

void DepthForwarder::onCameraInfo(const sensor_msgs::CameraInfo::ConstPtr& info) {
  try {
    const Intrinsics k = toIntrinsics(*info, "topic '" + cameraInfo_.getTopic() + "'");
    std::lock_guard lock(mutex_);
    intrinsics_ = k;
  } catch (const Error& e) {
    ROS_ERROR_THROTTLE(kWarnPeriodSeconds, "%s", e.what());
  }
}

void DepthForwarder::onDepth(const sensor_msgs::Image::ConstPtr& image) {
  std::lock_guard lock(mutex_);
  if (!intrinsics_) {
    ++skipped_;
    ROS_WARN_THROTTLE(kWarnPeriodSeconds, "no camera_info yet: %llu depth frame(s) skipped",
                      static_cast<unsigned long long>(skipped_));
    return;
  }
  const std::string where = "topic '" + depth_.getTopic() + "' frame seq " + std::to_string(image->header.seq);
  try {
    const double scale = config_.pushDepthScale > 0 ? config_.pushDepthScale : defaultDepthScale(image->encoding);
    const DepthRaw depth = toDepthRaw(*image, scale, where);
    if (depth.width() != intrinsics_->width || depth.height() != intrinsics_->height)
      throw Error(where + ": image " + std::to_string(depth.width()) + "x" + std::to_string(depth.height()) +
                  " differs from camera_info's " + std::to_string(intrinsics_->width) + "x" +
                  std::to_string(intrinsics_->height));
    PushedFrameHeader h;
    h.timestamp = image->header.stamp.toSec();
    h.depthScale = scale;
    h.fx = intrinsics_->fx;
    h.fy = intrinsics_->fy;
    h.cx = intrinsics_->cx;
    h.cy = intrinsics_->cy;
    if (!pusher_) pusher_ = std::make_unique<client::FramePusher>(config_.pushSocket);
    pusher_->push(h, depth);
    ++pushed_;
  } catch (const Error& e) {
    pusher_.reset();  // reconnect with the next frame (the daemon may be restarting)
    ROS_WARN_THROTTLE(kWarnPeriodSeconds, "depth frame not forwarded: %s", e.what());
  }
}

}  // namespace sb::ros_bridge
