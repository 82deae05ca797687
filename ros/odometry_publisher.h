#pragma once
// Publishes what slamboosterd reports on ROS topics: nav_msgs/Odometry per frame (stamped with the frame's
// capture time, covariance from the tracking state), the camera's TF, the tracking state as a
// std_msgs/String, and a diagnostic_msgs/DiagnosticArray per frame with the knobs, computation time and
// energy (the standard channel that rqt_robot_monitor and diagnostic_aggregator read).

#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <tf2_ros/transform_broadcaster.h>

#include <optional>
#include <string>

#include "ros/bridge_config.h"
#include "ros/daemon_reports.h"

namespace sb::ros_bridge {

class OdometryPublisher {
 public:
  OdometryPublisher(ros::NodeHandle& node, ros::NodeHandle& privateNode, const BridgeConfig& config);

  void onPose(const PoseReport& pose);
  // KNOBS follows its frame's POSE: the frame's diagnostics go out with it.
  void onKnobs(const KnobsReport& knobs);
  void onEnergy(const EnergyReport& energy);
  // The daemon is unreachable: diagnostics say so (ERROR), the state topic says "disconnected".
  void onDisconnected(const std::string& why);

 private:
  ros::Time stampOf(double timestamp) const;
  void publishDiagnostics(const KnobsReport* knobs);

  const BridgeConfig& config_;
  ros::Publisher odometry_;
  ros::Publisher state_;
  ros::Publisher diagnostics_;
  tf2_ros::TransformBroadcaster tf_;
  std::optional<PoseReport> lastPose_;
  std::optional<EnergyReport> lastEnergy_;
};

}  // namespace sb::ros_bridge
