#pragma once
// What the socket server asks of the rest of the daemon: the STATUS fields and applying ?CONTROL. Called
// on the event-loop thread; implementations must not block on the SLAM thread.

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "daemon/protocol.h"

namespace sb::daemon {

class ServiceState {
 public:
  virtual ~ServiceState() = default;
  // The STATUS fields (source, controller, meter, fps, drops, uptime ...), without "class".
  virtual nlohmann::json status() = 0;
  // Applies an authorised ?CONTROL request and returns the CONTROL reply fields (without "class"). Throws
  // sb::Error with a message for the ERROR reply when the request cannot be applied (nothing changes then).
  virtual nlohmann::json control(const ControlRequest& request) = 0;
  // Adds ?ODOM's samples to the live odometry and returns the ODOM reply fields (without "class"). Throws
  // sb::Error naming the sample when one is refused (the samples before it stay added), or when this daemon
  // takes no odometry from the socket.
  virtual nlohmann::json odometry(const OdomRequest& request);
};

inline nlohmann::json ServiceState::odometry(const OdomRequest&) {
  throw Error("?ODOM: this daemon takes no odometry from the socket");
}

}  // namespace sb::daemon
