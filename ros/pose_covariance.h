#pragma once
// The covariance of a published pose: what the tracking state says, in numbers (no ROS here). A good frame
// is certain to the configured sigmas; a weak one is uncertain along the motion its view does not constrain;
// a lost one is uncertain everywhere, so a consumer that fuses by covariance (robot_localization) ignores it.

#include <array>

#include "ros/bridge_config.h"
#include "ros/daemon_reports.h"

namespace sb::ros_bridge {

// Row-major 6x6 (x, y, z, rotation about x, y, z) in the parent frame, as nav_msgs/Odometry wants it.
using Covariance6 = std::array<double, 36>;

Covariance6 poseCovariance(const PoseReport& pose, const CovarianceConfig& config);

}  // namespace sb::ros_bridge
