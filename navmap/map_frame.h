#pragma once
// Which way is up (issue 45): the map frame of the navigation map, z up with z = 0 on the floor, given as a
// rigid transform from the SLAM world frame (the volume's frame: the first camera at initialPosition looking
// along +z, y down; architecture.md D2). Three sources:
//   - a configured camera mount (the first camera's height above the floor, pitch and roll): mapFrameFromMount;
//   - a floor fit: the dominant plane below the camera in a depth frame (fitFloor), which says what it found;
//   - odometry (REP 103: the odometry frame's z is up): mapFrameFromOdometry, world_T_odom =
//     T_world_camera(frame) * T_camera_to_odom(frame)^-1, from one frame's two poses.
// With none of them (a handheld camera) no grid is made and the run says why (navmap/nav_map.h).

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

namespace sb::navmap {

struct MapFrame {
  Eigen::Isometry3d T_world_to_map = Eigen::Isometry3d::Identity();  // maps world points into the map frame
  std::string source;  // "mount", "floor", "odometry": where it came from, with what it found
};

// The first camera's mount: where it sits above the floor and how it is tilted (the robot standing level).
struct CameraMount {
  double heightM = 0.0;   // optical centre above the floor, metres (> 0)
  double pitchDeg = 0.0;  // the optical axis below the horizon, degrees (positive: looking down)
  double rollDeg = 0.0;   // about the optical axis, degrees (positive: the image's right side down)
};

// The map frame of a camera mounted as `mount` whose pose in the world is `T_world_camera` (the first frame's):
// map x along the optical axis projected on the floor, y to the left, z up, origin on the floor below the camera.
MapFrame mapFrameFromMount(const Eigen::Isometry3d& T_world_camera, const CameraMount& mount);

// The hook for odometry (the lead's fusion fills it from a frame with both poses): the odometry frame is the
// map frame (its z up per REP 103; z = 0 at the odometry origin's height, the base on the floor by REP 105).
// world_T_odom = T_world_camera * T_camera_to_odom^-1, so T_world_to_map = world_T_odom^-1.
MapFrame mapFrameFromOdometry(const Eigen::Isometry3d& T_world_camera, const Eigen::Isometry3d& T_camera_to_odom);

struct FloorFitParams {
  double maxTiltDeg = 30.0;    // the floor's normal within this of the camera's -y (image up), degrees
  double minHeightM = 0.1;     // the plane at least this far below the camera, metres
  double inlierM = 0.04;       // a point within this of the plane counts for it, metres
  double minInlierShare = 0.05;  // of the valid pixels: fewer and no floor is found
  int iterations = 200;        // RANSAC hypotheses (seeded: the same points give the same plane)
};

struct FloorFit {
  Eigen::Vector3d normalCamera = Eigen::Vector3d::Zero();  // unit, towards the camera, camera frame
  double heightM = 0.0;                                    // camera above the plane, metres
  double inlierShare = 0.0;                                // of the points given
  CameraMount mount;                                       // the same as a mount (pitch, roll, height)
  std::string describe() const;                            // "floor 1.19 m below, pitch 3.2 deg, ..."
};

// The floor in camera-frame points (metres; e.g. a depth frame's back-projection): the largest plane whose
// normal points up within maxTiltDeg of the camera's -y and that lies at least minHeightM below the camera.
std::optional<FloorFit> fitFloor(const std::vector<Eigen::Vector3d>& pointsCamera, const FloorFitParams& params = {});

}  // namespace sb::navmap
