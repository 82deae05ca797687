#include "ros/odometry_publisher.h"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/console.h>
#include <std_msgs/String.h>
#include <time.h>

#include <cstdio>
#include <vector>

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

// How long a frame's publication waits for the robot's odometry at its stamp to reach the TF buffer, seconds:
// it normally is there already (the daemon used it for this frame); a base whose TF lags longer gets a held
// map -> odom for that frame, which diagnostics say.
constexpr double kOdometryWaitS = 0.05;

geometry_msgs::Pose toPose(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.linear());
  geometry_msgs::Pose p;
  p.position.x = T.translation().x();
  p.position.y = T.translation().y();
  p.position.z = T.translation().z();
  p.orientation.x = q.x();
  p.orientation.y = q.y();
  p.orientation.z = q.z();
  p.orientation.w = q.w();
  return p;
}

geometry_msgs::Transform toTransform(const Eigen::Isometry3d& T) {
  const geometry_msgs::Pose p = toPose(T);
  geometry_msgs::Transform t;
  t.translation.x = p.position.x;
  t.translation.y = p.position.y;
  t.translation.z = p.position.z;
  t.rotation = p.orientation;
  return t;
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
                                     const BridgeConfig& config, const OdometryForwarder* wheels)
    : config_(config), wheels_(wheels) {
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
  const Eigen::Isometry3d camera = cameraInMap(pose);
  const std::optional<RobotFrames> robot = wheels_ ? wheels_->robotFrames() : std::nullopt;
  // With the mount known the pose is the base's (robot_localization's frames); otherwise the camera's.
  const Eigen::Isometry3d child = robot ? camera * robot->cameraInBase.inverse() : camera;
  nav_msgs::Odometry odom;
  odom.header.stamp = stamp;
  odom.header.frame_id = config_.mapFrame;
  odom.child_frame_id = robot ? robot->baseFrame : config_.cameraFrame;
  odom.pose.pose = toPose(child);
  // The camera's covariance (the axes the daemon tracks); the base's position differs from it by the mount's
  // lever arm under the rotation's uncertainty, which this leaves out.
  const Covariance6 cov = poseCovariance(pose, config_.covariance);
  std::copy(cov.begin(), cov.end(), odom.pose.covariance.begin());
  odom.twist.covariance[0] = -1.0;  // the daemon does not estimate a twist (ROS convention for "unknown")
  odometry_.publish(odom);

  if (config_.publishTf) {
    if (robot) {
      publishMapToOdom(pose, stamp, camera, *robot);
    } else if (pose.keptMap == "localising") {
      // Started in a kept map and not localised in it yet (docs/map-store.md): the held pose is in no frame of
      // the store, so map -> ~camera_frame waits for the localised frame (map -> odom waits too: these frames
      // are lost, ros/map_to_odom.h, and the localised one's jump goes into it).
      tfEdge_ = "none: localising in the kept map";
    } else if (const auto parent = wheels_ ? wheels_->parentInTf(config_.cameraFrame) : std::nullopt;
               parent && *parent != config_.mapFrame) {
      // ~camera_frame is the robot's own (e.g. camera_depth_optical_frame under base_link, before the first
      // odometry): a second parent would break the robot's tree.
      tfEdge_ = "none: ~camera_frame '" + config_.cameraFrame + "' has the parent '" + *parent +
                "' in TF; leave ~camera_frame at slambooster_camera";
      ROS_WARN_THROTTLE(10.0, "slambooster: %s", tfEdge_.c_str());
    } else {
      geometry_msgs::TransformStamped t;
      t.header = odom.header;
      t.child_frame_id = config_.cameraFrame;
      t.transform = toTransform(camera);
      tf_.sendTransform(t);
      tfEdge_ = config_.mapFrame + " -> " + config_.cameraFrame;
    }
  }
  std_msgs::String state;
  state.data = trackingStateName(pose.state);
  state_.publish(state);
  lastPose_ = pose;
}

void OdometryPublisher::publishMapToOdom(const PoseReport& pose, const ros::Time& stamp,
                                         const Eigen::Isometry3d& cameraInMap, const RobotFrames& robot) {
  tfEdge_ = config_.mapFrame + " -> " + robot.odomFrame;
  std::string why;
  // A lost frame's pose is not used: no need to wait for the odometry at its stamp.
  const std::optional<Eigen::Isometry3d> cameraInOdom =
      pose.state == TrackingState::lost
          ? std::nullopt
          : wheels_->cameraInOdom(robot, stamp, kOdometryWaitS, why);
  const std::optional<MapOdomStep> step = mapToOdom_.onFrame(pose.frame, pose.state, cameraInMap, cameraInOdom);
  if (!step) {
    mapToOdomNote_ = "none yet: " + (why.empty() ? std::string("no tracked frame") : why);
    return;
  }
  mapToOdomNote_ = describe(*step);
  if (step->hold == MapOdomHold::noOdometry && !why.empty()) {
    mapToOdomNote_ += " (" + why + ")";
    ROS_WARN_THROTTLE(10.0, "slambooster: %s -> %s %s", config_.mapFrame.c_str(), robot.odomFrame.c_str(),
                      mapToOdomNote_.c_str());
  }
  std::vector<geometry_msgs::TransformStamped> out(1);
  out[0].header.stamp = stamp;
  out[0].header.frame_id = config_.mapFrame;
  out[0].child_frame_id = robot.odomFrame;
  out[0].transform = toTransform(step->mapToOdom);
  if (config_.transformToleranceS > 0) {  // for a lookup at "now" between frames (as AMCL, slam_toolbox)
    out.push_back(out[0]);
    // Never a later frame's own stamp (ros/map_to_odom.h), whose exact map -> odom tf2 would then ignore.
    out[1].header.stamp.fromNSec(static_cast<uint64_t>(
        forwardStampNs(static_cast<int64_t>(stamp.toNSec()), config_.transformToleranceS)));
  }
  tf_.sendTransform(out);
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
  s.level = levelOf(p.state);
  s.message = trackingStateName(p.state);
  if (p.state == TrackingState::lost && mapToOdomNote_.rfind("held", 0) == 0)
    s.message += "; " + tfEdge_ + " " + mapToOdomNote_ + " (the robot moves on its odometry)";
  s.values.push_back(keyValue("frame", std::to_string(p.frame)));
  s.values.push_back(keyValue("state", trackingStateName(p.state)));
  s.values.push_back(keyValue("tracked", p.tracked ? "true" : "false"));
  s.values.push_back(keyValue("corrected", p.corrected ? "true" : "false"));
  s.values.push_back(keyValue("constrained", p.constrained ? "true" : "false"));
  if (p.conditioning) s.values.push_back(keyValue("conditioning", number(*p.conditioning)));
  if (!p.weakestMotion.empty()) s.values.push_back(keyValue("weakest_motion", p.weakestMotion));
  if (!p.keptMap.empty()) s.values.push_back(keyValue("kept_map", p.keptMap));  // docs/map-store.md
  if (!tfEdge_.empty()) s.values.push_back(keyValue("tf", tfEdge_));
  if (!mapToOdomNote_.empty()) s.values.push_back(keyValue("map_to_odom", mapToOdomNote_));
  if (knobs) {
    s.values.push_back(keyValue("controller", knobs->controller));
    for (const auto& [key, value] : knobValues(*knobs)) s.values.push_back(keyValue(key, value));
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
