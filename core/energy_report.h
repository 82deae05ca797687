#pragma once
// The energy of one frame as the socket's ENERGY message carries it (docs/protocol.md): made by the daemon
// from the power meter's ledger (which may lag POSE), encoded by daemon/protocol.cpp, parsed by the ROS
// bridge (ros/daemon_reports.h). One type for both ends.

#include <cstdint>
#include <string>

namespace sb {

struct EnergyReport {
  uint64_t frame = 0;
  double joules = 0.0;     // the frame's energy
  double meanWatts = 0.0;  // over the frame's interval
  std::string meter;       // the power meter's name
};

}  // namespace sb
