#include "ros/daemon_link.h"

#include <ros/ros.h>

#include <nlohmann/json.hpp>

#include "client/connection.h"
#include "core/error.h"

namespace sb::ros_bridge {

namespace {

// How long one wait for the daemon's next line lasts before ros::ok() is checked again, seconds.
constexpr double kPollSeconds = 0.1;
constexpr int kProtoMajor = 1;  // the protocol major this bridge speaks (docs/protocol.md)
constexpr int kCloudMinor = 7;  // ?CLOUD since 1.7

}  // namespace

DaemonLink::DaemonLink(const BridgeConfig& config, OdometryPublisher& publisher, GridPublisher* grid,
                       CloudPublisher* cloud)
    : config_(config), publisher_(publisher), grid_(grid), cloud_(cloud) {}

std::string DaemonLink::serveOnce() {
  client::Connection connection(config_.socketPath, config_.connectTimeoutSeconds);
  const int major = connection.version().value("proto_major", -1);
  if (major != kProtoMajor)
    throw Error("slamboosterd at '" + config_.socketPath + "' speaks protocol " + std::to_string(major) +
                ", this bridge speaks " + std::to_string(kProtoMajor) + ": install matching versions");
  connection.send(R"(?WATCH={"enable":true,"pose":true,"knobs":true,"energy":true})");
  // An older daemon has no ?CLOUD.
  const bool cloud = cloud_ && connection.version().value("proto_minor", 0) >= kCloudMinor;
  announcedDown_ = false;
  ROS_INFO("connected to slamboosterd %s at %s", connection.version().value("release", "?").c_str(),
           config_.socketPath.c_str());
  ros::WallTime nextMap = ros::WallTime::now(), nextCloud = nextMap;
  while (ros::ok()) {
    if (grid_ && config_.mapPeriodSeconds > 0 && ros::WallTime::now() >= nextMap) {
      connection.send("?MAP;");  // the daemon's grid (protocol minor 4); an older daemon answers ERROR
      nextMap = ros::WallTime::now() + ros::WallDuration(config_.mapPeriodSeconds);
    }
    if (cloud && config_.cloudPeriodSeconds > 0 && ros::WallTime::now() >= nextCloud) {
      connection.send("?CLOUD;");  // the map's surface cells
      nextCloud = ros::WallTime::now() + ros::WallDuration(config_.cloudPeriodSeconds);
    }
    bool timedOut = false;
    auto message = connection.next(kPollSeconds, timedOut);
    if (timedOut) continue;
    if (!message) return "slamboosterd closed the connection";
    const std::string cls = message->value("class", "");
    if (cls == "POSE")
      publisher_.onPose(parsePose(*message));
    else if (cls == "KNOBS")
      publisher_.onKnobs(parseKnobs(*message));
    else if (cls == "ENERGY")
      publisher_.onEnergy(parseEnergy(*message));
    else if (cls == "MAP" && grid_)
      grid_->onMap(*message);
    else if (cls == "CLOUD" && cloud_)
      cloud_->onCloud(*message);
    else if (cls == "ERROR" && message->contains("retry_after_s"))
      // A rate limit (protocol 1.9: ~map_period_s or ~cloud_period_s under a second asks again for the grid
      // it has): the next period asks again.
      ROS_DEBUG("slamboosterd: %s", message->value("message", "").c_str());
    else if (cls == "ERROR")
      ROS_WARN("slamboosterd: %s", message->value("message", "").c_str());
    // Other classes (WATCH, future ones) are ignored, as the protocol asks.
  }
  return "shutting down";
}

void DaemonLink::run() {
  std::string lastError;
  while (ros::ok()) {
    std::string why;
    try {
      why = serveOnce();
    } catch (const std::exception& e) {
      why = e.what();
    }
    if (!ros::ok()) break;
    if (why != lastError) {  // say each new reason once, not every half second
      ROS_WARN("%s; retrying every %.1f s", why.c_str(), config_.reconnectSeconds);
      lastError = why;
    }
    if (!announcedDown_) publisher_.onDisconnected(why);  // once per outage, not every attempt
    announcedDown_ = true;
    ros::WallDuration(config_.reconnectSeconds).sleep();
  }
}

}  // namespace sb::ros_bridge
