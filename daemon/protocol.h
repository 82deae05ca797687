#pragma once
// The socket protocol (architecture.md D7; reference: docs/protocol.md): newline-delimited JSON, gpsd-style.
// Requests are single lines "?NAME;" or "?NAME={json object}" (a trailing ';' after the object is allowed);
// every reply and report is one JSON object with a "class" on one line.
//
// This file holds the pure parts: the request parser and the message encoders. No I/O.

#include <array>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/energy_report.h"
#include "core/pose_fields.h"
#include "daemon/odom_request.h"
#include "pipeline/knob_fields.h"
#include "core/tracking_state.h"

namespace sb::daemon {

constexpr int kProtoMajor = 1;
// 1: POSE carries constrained, conditioning, weakest_motion; 2: POSE carries state (good, weak, lost,
// relocalised) and STATUS a tracking_state object; 3: POSE carries velocity_m_per_frame, the frame log's name
// of its velocity (which it still carries as well); 4: the state `odometry`, POSE's odometry and
// odometry_drift_m (docs/odometry.md).
// 5: ?ODOM (any local client pushes the robot's odometry: daemon/odom_request.h).
// 6: ?MAP answers MAP, the navigation grid (issue 45; docs/navmap.md).
// 7: MAP carries frame_in_world (the grid's frame in POSE's) and octomap (map.bt's path); ?CLOUD answers CLOUD,
// the map's surface cells for a point cloud.
// 8: POSE carries odometry_fault, when the wheels and the view disagree (odometry/wheel_faults.h: disputed,
// slipping, kidnapped), as frames.jsonl's odometry.fault.
// 9: ?MAP and ?CLOUD rate-limited per connection (issue 53): the same reply at most once a second, sooner an
// ERROR carrying retry_after_s, the connection's next requests held that long (daemon/socket_server.h).
// 10: POSE carries kept_map in a run started with a kept map (docs/map-store.md): localising, localised.
// 11: STATUS carries kept_map, as the last frame's POSE (a pass started with a kept map; absent otherwise).
constexpr int kProtoMinor = 11;
// Deepest nesting accepted in a request argument (?CONTROL={"pin":{...}} needs 2).
constexpr int kMaxRequestDepth = 8;
// Longest controller name accepted in ?CONTROL (replies quote it; they must stay short).
constexpr size_t kMaxNameBytes = 64;

enum class Command { watch, poll, status, control, version, odom, map, cloud };

struct WatchRequest {  // fields absent from the request stay unset (the client's current choice is kept)
  std::optional<bool> enable, pose, knobs, energy;
};

struct ControlRequest {
  std::optional<std::string> controller;  // switch to this controller
  std::map<std::string, double> pin;      // knob name -> value; pd0/pd1/pd2 for the ICP iterations
  std::vector<std::string> unpin;         // knob names, or {"all"}
};

struct Request {
  Command command = Command::poll;
  WatchRequest watch;      // command == watch
  ControlRequest control;  // command == control
  OdomRequest odom;        // command == odom
};

struct ParseResult {
  std::optional<Request> request;
  std::string error;  // when !request: what was wrong, for the ERROR reply
};

// Parses one request line (without the '\n'; a trailing '\r' is ignored). Never throws.
ParseResult parseRequest(std::string_view line);

// One processed frame as the SLAM thread publishes it, typed: immutable once made (daemon/frame_report.h makes
// it from the frame's record). POSE is written from the pose record's table (core/pose_fields.h), KNOBS from
// the knob record's (pipeline/knob_fields.h): the tables frames.jsonl's encoder is made from too.
struct FrameReport {
  PoseFields pose;
  KnobFields knobs;  // with the knobs pinned over the controller's choice
};

// The navigation grid (navmap/) as the SLAM thread last wrote it: immutable once made.
struct MapReport {
  uint32_t pass = 0;
  uint64_t frame = 0;          // frames of the pass when it was made
  int width = 0, height = 0;   // cells
  double resolutionM = 0.05;   // cell side
  double originX = 0.0, originY = 0.0;  // map frame, metres: the lower-left corner of cell (0, 0)
  std::string up;              // where the map frame (z up) came from
  std::vector<int8_t> cells;   // row-major from cell (0, 0), row 0 the lowest y: -1 unknown, 0 free, 100 occupied
  // Since 1.7: the map frame's pose in the world frame (POSE's), T_map_to_world.
  std::array<double, 3> framePosition{};
  std::array<double, 4> frameQuaternion{0.0, 0.0, 0.0, 1.0};  // qx qy qz qw
  std::string octomap;         // map.bt's path as last written; "" when none is written
  // The cloud (?CLOUD): occupied 3D cells of cloudResolutionM in the map frame, cell (i, j, k) centred at
  // ((i, j, k) + 0.5) * cloudResolutionM; at most kMaxCloudCells. cloudResolutionM 0: no cloud.
  double cloudResolutionM = 0.0;
  std::vector<std::array<int32_t, 3>> cloud;
};

// The most cells a CLOUD carries (about 15 bytes each: well within socket.client_buffer_bytes' default 256 KiB).
inline constexpr size_t kMaxCloudCells = 8000;

nlohmann::json versionMessage(const std::string& release);
// MAP: the grid's cells run-length encoded as "runs": [value, count, value, count, ...] (nav_msgs/OccupancyGrid
// order and values).
nlohmann::json mapMessage(const MapReport& m);
// A voxel filter on the report's cloud: cells merged into cells twice as large (cloudResolutionM doubled) until
// at most maxCells (at least 8: the octants around the origin never merge) remain; sorted.
void boundCloud(MapReport& m, size_t maxCells);
// CLOUD: the report's cloud cells flattened as "cells": [i, j, k, i, j, k, ...] with "resolution".
nlohmann::json cloudMessage(const MapReport& m);
nlohmann::json poseMessage(const FrameReport& r);
nlohmann::json knobsMessage(const FrameReport& r);
nlohmann::json energyMessage(const EnergyReport& e);
nlohmann::json watchMessage(bool enable, bool pose, bool knobs, bool energy);
// `status`: fields of the STATUS object (source, controller, meter, fps, drops, uptime ...).
nlohmann::json statusMessage(nlohmann::json status);
nlohmann::json errorMessage(const std::string& message);

// One line on the wire: compact JSON + '\n'. Invalid UTF-8 in strings is replaced, never thrown.
std::string toLine(const nlohmann::json& message);

}  // namespace sb::daemon
