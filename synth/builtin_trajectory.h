#pragma once
// A built-in handheld-like camera trajectory for the procedural rooms, usable without any data: a slow
// orbit (radius 0.5 m, one turn per 40 s) around a point in the rooms' free floor space, the camera facing
// outwards and slightly down, with hand sway in position and orientation. World frame as the scenes
// (floor at +y); 30 frames per second.

#include <Eigen/Core>
#include <cstddef>

#include "core/trajectory.h"

namespace sb::synth {

struct BuiltinTrajectoryParams {
  double fps = 30.0;                // frames per second
  double orbitRadiusM = 0.5;        // metres
  double orbitPeriodS = 40.0;       // seconds per turn
  double centerX = 0.0, centerY = -0.1, centerZ = -1.2;  // orbit centre, metres (world; y down)
  double startAngleRad = 1.5707963267948966;              // starts on the +x side, facing +x
  double pitchDownRad = 0.2;        // mean downward tilt
  double swayPositionM = 0.04;      // amplitude of positional sway, metres
  double swayAngleRad = 0.05;       // amplitude of yaw/pitch/roll sway
};

// Camera-to-world rotation of a handheld camera that keeps its image "up" along world -y: forward (camera z) is
// (sin yaw, 0, cos yaw) turned down towards the floor (+y) by pitchDown, then rolled about forward. Radians.
Eigen::Matrix3d handheldRotation(double yaw, double pitchDown, double roll);

// `frames` poses, timestamps i / fps.
Trajectory builtinTrajectory(size_t frames, const BuiltinTrajectoryParams& params = {});

}  // namespace sb::synth
