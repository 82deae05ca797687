#pragma once
// Reads BridgeConfig from the node's private parameters (~socket, ~map_frame, ...) once at start-up and
// validates it. Throws sb::Error naming the parameter, its value and what is allowed.

#include <ros/node_handle.h>

#include "ros/bridge_config.h"

namespace sb::ros_bridge {

BridgeConfig readBridgeConfig(const ros::NodeHandle& privateNode);

}  // namespace sb::ros_bridge
