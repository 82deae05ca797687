#pragma once
// A bag's wheel odometry for the bag plugin (drivers/bag_plugin.h sbReadBagOdometry): nav_msgs/Odometry on
// one topic composed with the camera mount (the bag's /tf_static chain from the messages' child frame to the
// depth images' frame, or a given "x y z qx qy qz qw"): T_camera_to_odom samples (odometry/odometry_track.h)
// stamped with the messages' header stamps, the clock the depth frames carry (ros/bag_source.cpp).

#include <string>
#include <vector>

#include "drivers/odometry_sample.h"

namespace sb::ros_bridge {

// `topic` empty: the bag's only nav_msgs/Odometry topic (none: no samples; several: an error naming them).
// Throws sb::Error naming the bag, topic or missing transform.
std::vector<odometry::OdometrySample> readBagOdometry(const std::string& path, const std::string& topic,
                                                     const std::string& cameraMount, std::string& source);

// "x y z qx qy qz qw" as a pose; throws sb::Error naming `what` on anything else (a non-unit quaternion too).
Eigen::Isometry3d parseMount(const std::string& text, const std::string& what);

}  // namespace sb::ros_bridge
