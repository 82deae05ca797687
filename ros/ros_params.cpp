#include "ros/ros_params.h"

#include <cmath>

#include "core/error.h"

namespace sb::ros_bridge {

namespace {

void positive(const std::string& name, double value, const char* unit) {
  if (!(value > 0) || !std::isfinite(value))
    throw Error("parameter ~" + name + " = " + std::to_string(value) + " must be a positive number of " + unit);
}

void readSigma(const ros::NodeHandle& n, const std::string& state, StateSigma& sigma) {
  n.param("sigma_" + state + "_position_m", sigma.positionM, sigma.positionM);
  n.param("sigma_" + state + "_rotation_rad", sigma.rotationRad, sigma.rotationRad);
  positive("sigma_" + state + "_position_m", sigma.positionM, "metres");
  positive("sigma_" + state + "_rotation_rad", sigma.rotationRad, "radians");
}

}  // namespace

BridgeConfig readBridgeConfig(const ros::NodeHandle& n) {
  BridgeConfig c;
  n.param("socket", c.socketPath, c.socketPath);
  n.param("map_frame", c.mapFrame, c.mapFrame);
  n.param("camera_frame", c.cameraFrame, c.cameraFrame);
  n.param("publish_tf", c.publishTf, c.publishTf);
  n.param("transform_tolerance", c.transformToleranceS, c.transformToleranceS);
  n.param("stamp", c.stamp, c.stamp);
  n.param("reconnect_s", c.reconnectSeconds, c.reconnectSeconds);
  n.param("connect_timeout_s", c.connectTimeoutSeconds, c.connectTimeoutSeconds);
  n.param("grid_frame", c.gridFrame, c.gridFrame);
  n.param("map_period_s", c.mapPeriodSeconds, c.mapPeriodSeconds);
  n.param("cloud_period_s", c.cloudPeriodSeconds, c.cloudPeriodSeconds);
  readSigma(n, "good", c.covariance.good);
  readSigma(n, "relocalised", c.covariance.relocalised);
  readSigma(n, "weak", c.covariance.weak);
  readSigma(n, "weak_axis", c.covariance.weakAxis);
  readSigma(n, "lost", c.covariance.lost);
  readSigma(n, "odometry", c.covariance.odometry);
  n.param("odometry_drift_sigma_per_m", c.covariance.odometryDriftPerM, c.covariance.odometryDriftPerM);
  n.param("push_socket", c.pushSocket, c.pushSocket);
  n.param("depth_topic", c.depthTopic, c.depthTopic);
  n.param("camera_info_topic", c.cameraInfoTopic, c.cameraInfoTopic);
  n.param("push_depth_scale", c.pushDepthScale, c.pushDepthScale);
  n.param("odom_topic", c.odomTopic, c.odomTopic);
  n.param("odom_camera_frame", c.odomCameraFrame, c.odomCameraFrame);
  if (!c.odomTopic.empty() && c.odomCameraFrame.empty())
    throw Error("parameter ~odom_camera_frame is empty while ~odom_topic is set: name the depth camera's optical frame");

  if (c.socketPath.empty()) throw Error("parameter ~socket is empty: give slamboosterd's socket path");
  if (c.mapFrame.empty() || c.cameraFrame.empty() || c.mapFrame == c.cameraFrame)
    throw Error("parameters ~map_frame ('" + c.mapFrame + "') and ~camera_frame ('" + c.cameraFrame +
                "') must be two different, non-empty frame ids");
  if (c.stamp != "frame" && c.stamp != "monotonic")
    throw Error("parameter ~stamp = '" + c.stamp + "' must be \"frame\" or \"monotonic\"");
  positive("reconnect_s", c.reconnectSeconds, "seconds");
  if (c.transformToleranceS != 0) positive("transform_tolerance", c.transformToleranceS, "seconds (or 0: stamp only)");
  if (c.mapPeriodSeconds != 0) positive("map_period_s", c.mapPeriodSeconds, "seconds (or 0: no ~map)");
  if (c.cloudPeriodSeconds != 0) positive("cloud_period_s", c.cloudPeriodSeconds, "seconds (or 0: no ~cloud)");
  positive("connect_timeout_s", c.connectTimeoutSeconds, "seconds");
  if (c.pushDepthScale != 0) positive("push_depth_scale", c.pushDepthScale, "raw units per metre (or 0)");
  if (!c.pushSocket.empty() && c.depthTopic.empty())
    throw Error("parameter ~depth_topic is empty while ~push_socket is set: name the depth image topic");
  return c;
}

}  // namespace sb::ros_bridge
