#pragma once
// What the ROS bridge reads from slamboosterd's socket (docs/protocol.md): POSE, KNOBS and ENERGY reports as
// typed structs. No ROS here, so the parsing is tested on its own. Unknown members are ignored (the protocol's
// rule); a missing optional member keeps its default. POSE is read into the pose record (core/pose_fields.h)
// and KNOBS into the knob record (pipeline/knob_fields.h), each member by its row of the record's table, the
// table the daemon writes the message from: the bridge keeps no list of its own.

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <utility>
#include <vector>

#include "core/energy_report.h"
#include "core/pose_fields.h"
#include "core/tracking_state.h"
#include "pipeline/knob_fields.h"

namespace sb::ros_bridge {

// The tracking state of one frame: the daemon's one enum (core/tracking_state.h, docs/tracking-state.md).
using sb::TrackingState;
using sb::trackingStateName;

// A POSE as the daemon wrote it: its pose record. A member POSE lacks keeps the record's default (constrained:
// true, as when the conditioning is not known).
using PoseReport = sb::PoseFields;
// A KNOBS as the daemon wrote it: its knob record (the knobs each under its name in pipeline/knobs.h's table).
using KnobsReport = sb::KnobFields;

// Parse one report. Throws sb::Error naming the class and member when a required member is missing or of
// the wrong type (a daemon of another major version, or not a daemon). POSE requires frame, timestamp,
// position, quaternion and tracked; KNOBS the frame and every knob.
// POSE's `state` is its state member when present and known; an unknown state string counts as lost (a state
// this bridge cannot interpret must not look certain); without the member (a daemon before protocol 1.2) it is
// derived from the older members: not tracked -> lost; corrected (an extrapolated pose) or constrained == false
// -> weak; else good. The velocity is read under its name since protocol 1.3, else under the older one.
PoseReport parsePose(const nlohmann::json& j);
KnobsReport parseKnobs(const nlohmann::json& j);
// The knobs as the diagnostics' key values, in the table's order: each knob's name and value (%.6g; pd's three
// levels joined by ',').
std::vector<std::pair<std::string, std::string>> knobValues(const KnobsReport& k);
EnergyReport parseEnergy(const nlohmann::json& j);

}  // namespace sb::ros_bridge
