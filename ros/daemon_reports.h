#pragma once
// What the ROS bridge reads from slamboosterd's socket (docs/protocol.md): POSE, KNOBS and ENERGY reports as
// typed structs. No ROS here, so the parsing is tested on its own. Unknown members are ignored (the protocol's
// rule); a missing optional member keeps its default. POSE's members are read by their names in the pose
// record's table (core/pose_fields.h), the table the daemon writes POSE from; KNOBS's knobs by pipeline/knobs.h's.

#include <array>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/energy_report.h"
#include "core/tracking_state.h"
#include "pipeline/knobs.h"

namespace sb::ros_bridge {

// The tracking state of one frame: the daemon's one enum (core/tracking_state.h, docs/tracking-state.md).
using sb::TrackingState;
using sb::trackingStateName;

struct PoseReport {
  uint64_t frame = 0;
  double timestamp = 0.0;                 // the frame's capture time, seconds (see docs/protocol.md)
  std::array<double, 3> position{};       // T_camera_to_world translation, metres
  std::array<double, 4> quaternion{0, 0, 0, 1};  // [qx, qy, qz, qw]
  bool tracked = false;
  bool corrected = false;
  double velocity = 0.0;                  // metres per frame
  std::optional<bool> constrained;        // protocol 1.1
  std::optional<double> conditioning;
  std::string weakestMotion;              // "tx".."rz", empty when absent
  std::optional<std::string> state;       // the daemon's own state string when it sends one
  bool odometry = false;                  // protocol 1.4: the frame had an odometry pose
  double odometryDriftM = 0.0;            // protocol 1.4: metres driven on odometry alone (state odometry)
  std::string keptMap;                    // protocol 1.9: "localising" / "localised" in a kept map, else empty
  TrackingState trackingState = TrackingState::lost;  // `state` when known, else derived (trackingStateOf)
};

struct KnobsReport {
  uint64_t frame = 0;
  std::string controller;
  Knobs knobs;  // each under its name in pipeline/knobs.h's table
  double computationMs = 0.0;
};

// The state a POSE says: its `state` member when present and known; otherwise derived from the older members:
// not tracked -> lost; corrected (an extrapolated pose) or constrained == false -> weak; else good. An
// unknown state string counts as lost: a state this bridge cannot interpret must not look certain.
TrackingState trackingStateOf(const PoseReport& pose);

// Parse one report. Throws sb::Error naming the class and member when a required member is missing or of
// the wrong type (a daemon of another major version, or not a daemon).
PoseReport parsePose(const nlohmann::json& j);
KnobsReport parseKnobs(const nlohmann::json& j);
// The knobs as the diagnostics' key values, in the table's order: each knob's name and value (%.6g; pd's three
// levels joined by ',').
std::vector<std::pair<std::string, std::string>> knobValues(const KnobsReport& k);
EnergyReport parseEnergy(const nlohmann::json& j);

}  // namespace sb::ros_bridge
