#pragma once
// The `source` section of the daemon's configuration (config/slamboosterd.json, key table in
// config/README.md): the settings of the frame sources (daemon/source_registry.h), read and written here, not
// by the daemon's config (daemon_config.h only holds the section). A key shared by several sources (path:
// replay and push; camera: openni2 and pattern) is one key; adding one touches this file pair,
// config/slamboosterd.json and config/README.md (test_daemon_config checks that the file lists every key at
// its default).

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "core/config_reader.h"

namespace sb::daemon {

// source.camera: a live camera (source.type "openni2"; replay ignores it).
struct CameraConfig {
  std::string uri;                        // OpenNI2 device URI; empty = the first device found
  int width = 640;                        // depth mode, pixels
  int height = 480;                       // depth mode, pixels
  int fps = 30;                           // depth mode, frames per second
  double fx = 0, fy = 0, cx = 0, cy = 0;  // intrinsics, pixels; 0 = from the device's field of view
  double frameTimeoutSeconds = 2.0;       // no frame for this long: the camera counts as lost
  double reconnectMinSeconds = 0.5;   // first wait before reopening a lost camera; doubles per failed attempt
  double reconnectMaxSeconds = 10.0;  // longest wait between attempts

  void read(ConfigReader& reader);  // the keys below, by their JSON names (config/README.md)
  nlohmann::json toJson() const;    // every key read() reads, with its value
};

struct SourceConfig {
  std::string type = "replay";      // a registered source (daemon/source_registry.cpp)
  std::string path;                 // replay: sequence directory (TUM layout), .raw or .bag file; push: its
                                    // socket; required
  std::string pacing = "recorded";  // "recorded": frames at their recorded timestamps; "fast": no waiting
  double speed = 1.0;               // recorded pacing only: playback speed factor
  std::string atEnd = "stop";       // "stop": keep serving the socket; "loop": replay again; "exit": exit 0
  size_t maxFrames = 0;             // frames per pass (0 = all)
  double depthScale = 0.0;          // raw units per metre; 0 = from calibration.json / the format
  size_t queueFrames = 4;           // capacity of the capture -> SLAM queue (frames)
  std::string depthTopic;           // replay of a ROS bag: its depth image topic; empty = the bag's only one
  // The robot's odometry (odometry/odometry_input.h): "auto" = a replay's SEQ/odometry.txt (a bag's Odometry
  // topic) when it has one, else what clients push with ?ODOM; "socket" = only ?ODOM; "none"; or a file's path.
  std::string odometry = "auto";
  std::string odomTopic;    // replay of a ROS bag: its nav_msgs/Odometry topic; empty = the bag's only one
  std::string cameraMount;  // replay of a ROS bag: "x y z qx qy qz qw" of the camera in the base; empty = /tf_static
  double pushTimeoutSeconds = 5.0;  // push: a client silent this long within or before a frame is closed
  size_t maxFramePixels = 1310720;  // push: largest frame accepted, width x height pixels (1280x1024)
  unsigned socketMode = 0660;       // push: its socket's permission bits; not a key: socket.mode, set by the
                                    // daemon (the push socket follows the control socket)
  CameraConfig camera;              // type "openni2" (and "pattern": its size and rate)

  // The `source` section's keys (config/README.md); type must be a registered source.
  void read(ConfigReader& reader);
  nlohmann::json toJson() const;  // every key read() reads, with its value
};

}  // namespace sb::daemon
