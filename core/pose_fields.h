#pragma once
// The pose record of one frame: its final pose and tracking state as the daemon's POSE message carries them
// (docs/protocol.md) and frames.jsonl writes them (runtime/frame_log_sink.h). Each field is written once, in
// forEachPoseField's table (its POSE name, its frames.jsonl name, its member, its unit), as report/run_summary.cpp
// keeps summary.json's sections and gpsd its json_attr_t tables. Both encoders are made from the table:
// frames.jsonl's (frameRecordToJson) and POSE's (daemon/protocol.cpp, poseMessage); runtime/frame_log_sink.h's
// poseFieldsOf makes the record from a frame's FrameRecord, the one projection both use. A field added here is
// written by both. tests/daemon/test_frame_report.cpp checks every row against both encodings.
//
// The rule both encoders keep: a field without a value (an empty std::optional, an empty string) is absent.
// The readers name the fields by the table too (poseField): POSE's in ros/daemon_reports.cpp, frames.jsonl's in
// report/frame_log.cpp.

#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <type_traits>

#include "core/field_row.h"
#include "core/tracking_state.h"

namespace sb {

struct PoseFields {
  uint64_t frame = 0;
  double timestamp = 0.0;                        // seconds, the frame's capture time
  std::array<double, 3> position{};              // T_camera_to_world translation, metres
  std::array<double, 4> quaternion{0, 0, 0, 1};  // qx, qy, qz, qw
  bool tracked = false;
  bool corrected = false;
  TrackingState state = TrackingState::good;
  double velocityMPerFrame = 0.0;
  std::optional<double> conditioning;  // when ICP ran
  std::string weakestMotion;           // "tx".."rz" when ICP ran, else empty
  bool constrained = true;             // true when the conditioning is not known
  // Protocol 1.4, the robot's odometry (docs/odometry.md): the frame had an odometry pose at its stamp, and
  // the distance driven on odometry alone since depth last tracked (metres; 0 unless state is odometry).
  bool odometry = false;
  double odometryDriftM = 0.0;
  // Protocol 1.8: the wheels and the view disagree (odometry/wheel_faults.h); "" when they do not.
  std::string odometryFault;
  // Protocol 1.9: a run started with a kept map (docs/map-store.md): "localising" (the pose is in no frame
  // of the store yet; the state is lost) or "localised" (the pose is in the store's frame); "" without one.
  std::string keptMap;
};

// One row of the table.
struct PoseField {
  const char* name;       // POSE's member
  const char* logName;    // frames.jsonl's key for the same value; nullptr: not in frames.jsonl
  const char* logObject;  // the frames.jsonl object that holds logName (nullptr: the line itself); the field is
                          // written only in a line that has that object (frames.jsonl's odometry: runs with odometry)
  const char* logWith;    // frames.jsonl writes the field only beside this key, one of an earlier row (nullptr: always)
  const char* unit;       // "" for flags, names and counts
};

// POSE's name of the velocity before protocol 1.3, kept for the clients of 1.0-1.2 (a row of its own).
inline constexpr const char* kPoseLegacyVelocity = "velocity";

// Calls field(row, member) for each field, in the table's order. `P` is PoseFields or const PoseFields.
template <typename P, typename Field>
void forEachPoseField(P& p, Field&& field) {
  field(PoseField{"frame", "frame", nullptr, nullptr, ""}, p.frame);
  field(PoseField{"timestamp", "timestamp", nullptr, nullptr, "s"}, p.timestamp);
  field(PoseField{"position", "position", nullptr, nullptr, "m"}, p.position);
  field(PoseField{"quaternion", "quaternion", nullptr, nullptr, ""}, p.quaternion);
  field(PoseField{"tracked", "tracked", nullptr, nullptr, ""}, p.tracked);
  field(PoseField{"corrected", "corrected", nullptr, nullptr, ""}, p.corrected);
  field(PoseField{"state", "state", nullptr, nullptr, ""}, p.state);
  field(PoseField{"velocity_m_per_frame", "velocity_m_per_frame", nullptr, nullptr, "m/frame"}, p.velocityMPerFrame);
  field(PoseField{kPoseLegacyVelocity, nullptr, nullptr, nullptr, "m/frame"}, p.velocityMPerFrame);
  field(PoseField{"conditioning", "conditioning", nullptr, nullptr, ""}, p.conditioning);
  field(PoseField{"weakest_motion", "weakest_motion", nullptr, nullptr, ""}, p.weakestMotion);
  field(PoseField{"constrained", "constrained", nullptr, "conditioning", ""}, p.constrained);
  field(PoseField{"odometry", "available", "odometry", nullptr, ""}, p.odometry);
  field(PoseField{"odometry_drift_m", "drift_m", "odometry", nullptr, "m"}, p.odometryDriftM);
  field(PoseField{"odometry_fault", "fault", "odometry", nullptr, ""}, p.odometryFault);
  field(PoseField{"kept_map", "kept_map", nullptr, nullptr, ""}, p.keptMap);
}

// The row of a member (its first: the velocity's is velocity_m_per_frame): poseField(&PoseFields::timestamp).name
// is "timestamp". Every member has a row (tests/daemon/test_frame_report.cpp).
template <typename M>
PoseField poseField(M PoseFields::*member) {
  return fieldRowOf<PoseField>(member, [](const PoseFields& r, auto&& visit) { forEachPoseField(r, visit); });
}

// Calls write(row, value) for each field that has a value, the value as JSON (a state by its name), in the
// table's order: what both encoders write.
template <typename Write>
void forEachPoseValue(const PoseFields& p, Write&& write) {
  forEachPoseField(p, [&](const PoseField& row, const auto& member) {
    using T = std::decay_t<decltype(member)>;
    if constexpr (std::is_same_v<T, TrackingState>)
      write(row, nlohmann::json(trackingStateName(member)));
    else if constexpr (std::is_same_v<T, std::string>) {
      if (!member.empty()) write(row, nlohmann::json(member));
    } else if constexpr (std::is_same_v<T, std::optional<double>>) {
      if (member) write(row, nlohmann::json(*member));
    } else {
      write(row, nlohmann::json(member));
    }
  });
}

}  // namespace sb
