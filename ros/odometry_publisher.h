#pragma once
// Publishes what slamboosterd reports on ROS topics: nav_msgs/Odometry per frame (stamped with the frame's
// capture time, covariance from the tracking state), the camera's TF, the tracking state as a
// std_msgs/String, and a diagnostic_msgs/DiagnosticArray per frame with the knobs, computation time and
// energy (the standard channel that rqt_robot_monitor and diagnostic_aggregator read).
// The TF it publishes per frame (issue 57, docs/ros.md "The TF tree"): once the robot's odometry is known
// (~odom_topic, ros/odometry_forwarder.h) REP 105's map -> odom (ros/map_to_odom.h) at the frame's stamp and
// again forward-dated by ~transform_tolerance, and the odometry's pose is the base's; before that, and without
// ~odom_topic, map -> ~camera_frame, a frame of the bridge's own.

#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <tf2_ros/transform_broadcaster.h>

#include <optional>
#include <string>

#include "ros/bridge_config.h"
#include "ros/daemon_reports.h"
#include "ros/map_to_odom.h"
#include "ros/odometry_forwarder.h"

namespace sb::ros_bridge {

class OdometryPublisher {
 public:
  // `wheels`: the robot's odometry (borrowed; nullptr without ~odom_topic).
  OdometryPublisher(ros::NodeHandle& node, ros::NodeHandle& privateNode, const BridgeConfig& config,
                    const OdometryForwarder* wheels = nullptr);

  void onPose(const PoseReport& pose);
  // KNOBS follows its frame's POSE: the frame's diagnostics go out with it.
  void onKnobs(const KnobsReport& knobs);
  void onEnergy(const EnergyReport& energy);
  // The daemon is unreachable: diagnostics say so (ERROR), the state topic says "disconnected".
  void onDisconnected(const std::string& why);

 private:
  ros::Time stampOf(double timestamp) const;
  void publishDiagnostics(const KnobsReport* knobs);
  // map -> odom for this frame (its stamp and forward-dated), held when lost or without odometry at the stamp.
  void publishMapToOdom(const PoseReport& pose, const ros::Time& stamp, const Eigen::Isometry3d& cameraInMap,
                        const RobotFrames& robot);

  const BridgeConfig& config_;
  const OdometryForwarder* wheels_;
  MapToOdom mapToOdom_;
  std::string tfEdge_;          // the edge the last frame published, for diagnostics ("map -> odom")
  std::string mapToOdomNote_;   // describe() of the last map -> odom step, or why there is none yet
  ros::Publisher odometry_;
  ros::Publisher state_;
  ros::Publisher diagnostics_;
  tf2_ros::TransformBroadcaster tf_;
  std::optional<PoseReport> lastPose_;
  std::optional<EnergyReport> lastEnergy_;
};

}  // namespace sb::ros_bridge
