#include "ros/odometry_publisher.h"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <std_msgs/String.h>
#include <time.h>

#include <cstdio>

#include "core/error.h"
#include "ros/pose_covariance.h"

namespace sb::ros_bridge {

namespace {

constexpr uint32_t kQueue = 100;  // messages buffered per subscriber connection: 3 s at 30 fps
constexpr const char* kDiagnosticName = "slambooster: tracking";

diagnostic_msgs::KeyValue keyValue(const std::string& key, const std::string& value) {
  diagnostic_msgs::KeyValue kv;
  kv.key = key;
  kv.value = value;
  return kv;
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

uint8_t levelOf(TrackingState state) {
  switch (state) {
    case TrackingState::good: return diagnostic_msgs::DiagnosticStatus::OK;
    case TrackingState::weak:
    case TrackingState::relocalised:
    case TrackingState::odometry: return diagnostic_msgs::DiagnosticStatus::WARN;
    case TrackingState::lost: return diagnostic_msgs::DiagnosticStatus::ERROR;
  }
  return diagnostic_msgs::DiagnosticStatus::ERROR;
}

}  // namespace

OdometryPublisher::OdometryPublisher(ros::NodeHandle& node, ros::NodeHandle& privateNode,
                                     const BridgeConfig& config)
    : config_(config) {
  odometry_ = privateNode.advertise<nav_msgs::Odometry>("odometry", kQueue);
  state_ = privateNode.advertise<std_msgs::String>("tracking_state", kQueue, /*latch=*/true);
  diagnostics_ = node.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", kQueue);
}

ros::Time OdometryPublisher::stampOf(double timestamp) const {
  if (config_.stamp == "monotonic") {
    timespec now{};
    clock_gettime(CLOCK_MONOTONIC, &now);
    const double ageSeconds = (now.tv_sec + now.tv_nsec * 1e-9) - timestamp;
    return ros::Time::now() - ros::Duration(ageSeconds);
  }
  return ros::Time(timestamp);
}

void OdometryPublisher::onPose(const PoseReport& pose) {
  const ros::Time stamp = stampOf(pose.timestamp);
  nav_msgs::Odometry odom;
  odom.header.stamp = stamp;
  odom.header.frame_id = config_.mapFrame;
  odom.child_frame_id = config_.cameraFrame;
  odom.pose.pose.position.x = pose.position[0];
  odom.pose.pose.position.y = pose.position[1];
  odom.pose.pose.position.z = pose.position[2];
  odom.pose.pose.orientation.x = pose.quaternion[0];
  odom.pose.pose.orientation.y = pose.quaternion[1];
  odom.pose.pose.orientation.z = pose.quaternion[2];
  odom.pose.pose.orientation.w = pose.quaternion[3];
  const Covariance6 cov = poseCovariance(pose, config_.covariance);
  std::copy(cov.begin(), cov.end(), odom.pose.covariance.begin());
  odom.twist.covariance[0] = -1.0;  // the daemon does not estimate a twist (ROS convention for "unknown")
  odometry_.publish(odom);

  if (config_.publishTf) {
    geometry_msgs::TransformStamped t;
    t.header = odom.header;
    t.child_frame_id = config_.cameraFrame;
    t.transform.translation.x = pose.position[0];
    t.transform.translation.y = pose.position[1];
    t.transform.translation.z = pose.position[2];
    t.transform.rotation = odom.pose.pose.orientation;
    tf_.sendTransform(t);
  }
  std_msgs::String state;
  state.data = trackingStateName(pose.trackingState);
  state_.publish(state);
  lastPose_ = pose;
}

void OdometryPublisher::onKnobs(const KnobsReport& knobs) {
  if (lastPose_ && lastPose_->frame == knobs.frame) publishDiagnostics(&knobs);
}

void OdometryPublisher::onEnergy(const EnergyReport& energy) { lastEnergy_ = energy; }

void OdometryPublisher::publishDiagnostics(const KnobsReport* knobs) {
  diagnostic_msgs::DiagnosticStatus s;
  s.name = kDiagnosticName;
  s.hardware_id = config_.socketPath;
  const PoseReport& p = *lastPose_;
  s.level = levelOf(p.trackingState);
  s.message = trackingStateName(p.trackingState);
  s.values.push_back(keyValue("frame", std::to_string(p.frame)));
  s.values.push_back(keyValue("state", trackingStateName(p.trackingState)));
  s.values.push_back(keyValue("tracked", p.tracked ? "true" : "false"));
  s.values.push_back(keyValue("corrected", p.corrected ? "true" : "false"));
  if (p.constrained) s.values.push_back(keyValue("constrained", *p.constrained ? "true" : "false"));
  if (p.conditioning) s.values.push_back(keyValue("conditioning", number(*p.conditioning)));
  if (!p.weakestMotion.empty()) s.values.push_back(keyValue("weakest_motion", p.weakestMotion));
  if (knobs) {
    s.values.push_back(keyValue("controller", knobs->controller));
    s.values.push_back(keyValue("csr", number(knobs->csr)));
    s.values.push_back(keyValue("icp", number(knobs->icp)));
    s.values.push_back(keyValue("pd", number(knobs->pd[0]) + "," + number(knobs->pd[1]) + "," + number(knobs->pd[2])));
    s.values.push_back(keyValue("tr", number(knobs->tr)));
    s.values.push_back(keyValue("ir", number(knobs->ir)));
    s.values.push_back(keyValue("computation_ms", number(knobs->computationMs)));
  }
  if (lastEnergy_) {  // ENERGY lags POSE: the latest known frame's
    s.values.push_back(keyValue("energy_frame", std::to_string(lastEnergy_->frame)));
    s.values.push_back(keyValue("joules", number(lastEnergy_->joules)));
    s.values.push_back(keyValue("mean_w", number(lastEnergy_->meanWatts)));
  }
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = stampOf(p.timestamp);
  array.status.push_back(std::move(s));
  diagnostics_.publish(array);
}

void OdometryPublisher::onDisconnected(const std::string& why) {
  diagnostic_msgs::DiagnosticStatus s;
  s.name = kDiagnosticName;
  s.hardware_id = config_.socketPath;
  s.level = diagnostic_msgs::DiagnosticStatus::ERROR;
  s.message = "slamboosterd unreachable: " + why;
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = ros::Time::now();
  array.status.push_back(std::move(s));
  diagnostics_.publish(array);
  std_msgs::String state;
  state.data = "disconnected";
  state_.publish(state);
  lastPose_.reset();
}

}  // namespace sb::ros_bridge
