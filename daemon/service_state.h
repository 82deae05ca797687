#pragma once
// What the socket server asks of the rest of the daemon: the STATUS fields and applying ?CONTROL. Called
// on the event-loop thread; implementations must not block on the SLAM thread.

#include <nlohmann/json.hpp>

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
};

}  // namespace sb::daemon
