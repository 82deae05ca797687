#pragma once
// slambooster_ros's settings: one typed struct (units in the names), read once from the node's private ROS
// parameters (ros_params.cpp) and validated there. docs/ros.md has the table.

#include <string>

namespace sb::ros_bridge {

// Standard deviations of the published pose per tracking state, in the camera's own axes (x right, y down,
// z forward); the odometry's covariance is these squared and rotated into the parent frame.
struct StateSigma {
  double positionM = 0.0;     // metres
  double rotationRad = 0.0;   // radians
};

struct CovarianceConfig {
  StateSigma good{0.01, 0.01};        // a tracked, well-constrained frame
  StateSigma relocalised{0.05, 0.05}; // just recovered: right, but not yet confirmed by a run of good frames
  StateSigma weak{0.01, 0.01};        // the axes the view constrains
  StateSigma weakAxis{1.0, 1.0};      // the weakest motion (or every axis when the daemon does not name one)
  StateSigma lost{1000.0, 3.14159};   // the pose is the last good one, held: it says nothing about now
  StateSigma odometry{0.05, 0.05};    // the pose follows the wheels alone (state odometry), plus the drift below
  double odometryDriftPerM = 0.05;    // ... plus this many metres (radians) of sigma per metre driven on them
};

struct BridgeConfig {
  std::string socketPath = "/run/slambooster/slambooster.sock";  // slamboosterd's socket
  std::string mapFrame = "map";                  // parent frame: the daemon's volume frame
  std::string cameraFrame = "slambooster_camera";  // child frame: the depth camera's optical frame
  bool publishTf = true;  // also broadcast on /tf: map_frame -> the odometry's frame once the robot's odometry
                          // is known (REP 105), map_frame -> camera_frame before that and without odom_topic
  double transformToleranceS = 0.1;  // map -> odom is also sent stamped this much after the frame (AMCL's
                                     // transform_tolerance), so that lookups at "now" succeed between frames
  std::string stamp = "frame";  // "frame": the POSE timestamp as is (replays, depth from a ROS topic);
                                // "monotonic": the daemon's CLOCK_MONOTONIC (a live OpenNI2 camera) mapped to ROS time
  double reconnectSeconds = 0.5;  // wait between attempts to reach the daemon
  double connectTimeoutSeconds = 2.0;  // for the VERSION greeting and the WATCH reply
  CovarianceConfig covariance;
  // The navigation grid (issue 45): ?MAP every mapPeriodSeconds, published latched on ~map in gridFrame.
  std::string gridFrame = "slambooster_grid";  // the map frame of the grid: z up, z = 0 the floor
  double mapPeriodSeconds = 5.0;               // 0: no ~map
  double cloudPeriodSeconds = 5.0;             // ?CLOUD every this many seconds onto ~cloud; 0: no ~cloud
  // Depth from ROS topics into the daemon (empty push_socket: off).
  std::string pushSocket;                      // the daemon's push source socket (source.type "push")
  std::string depthTopic = "camera/depth/image";  // sensor_msgs/Image, 16UC1 (mm) or 32FC1 (m)
  std::string cameraInfoTopic;                 // empty: camera_info beside depth_topic
  // The robot's odometry into the daemon (?ODOM; empty odom_topic: off).
  std::string odomTopic = "/odom";                               // nav_msgs/Odometry
  std::string odomCameraFrame = "camera_depth_optical_frame";  // the depth camera's optical frame in TF
  double pushDepthScale = 0.0;  // raw units per metre of the frames handed to the daemon; 0 = from the
                                // encoding (16UC1: 1000, its millimetres as they are; 32FC1: 5000, 0.2 mm)
};

}  // namespace sb::ros_bridge
