#pragma once
// The floor's up in a depth frame (issue 52; docs/wheel-faults.md "The mount's tilt, from the floor"). A wheeled
// base stands on its floor: the floor's normal, as the camera sees it, is the base's up axis in the camera frame,
// whatever the mount was measured to be. A mount a degree or two off in tilt turns the wheels' turns about an
// axis as far off, and in a U-turn whose view leaves the roll free (facing the corridor's end wall) the map leans
// by twice that (docs/wheel-faults.md). Learning the tilt from the turns needs 90 degrees of turning the view
// fixes; the floor shows it on every frame of the first straight.
//
// Every horizontal surface shares the floor's normal (a table top, a step). The surfaces within kFloorConeDeg of
// the up the mount assumes are found by their normals (on a grid of about 80 columns, each from its neighbours one
// cell away where the three points of each direction lie on a line: an edge or a depth jump is no surface), then
// those within kFloorTrimDeg of their mean (a ramp's or a slanted surface's normals go); the up is the normal of
// the plane fitted to the points at their middle height (floor_up.cpp fitPlane: the normals alone lean towards the
// camera by most of a degree on a floor seen at a grazing angle).

#include <Eigen/Geometry>
#include <cstddef>
#include <optional>

#include "core/image.h"
#include "core/intrinsics.h"

namespace sb::odometry {

struct FloorUp {
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  // unit, in the camera frame, on the camera's side of the floor
  size_t samples = 0;                             // the points of the plane fitted
  double share = 0.0;                             // of the grid points with a reading, those facing up
};

// The up of the horizontal surfaces `depth` shows, searched within kConeDeg of `assumedUp` (the camera frame's up
// as the mount says); none when they cover less than kMinShare of the grid's points with a reading (a view into
// a wall, a covered lens). `depthScale`: raw units per metre; `k`: the depth image's intrinsics.
std::optional<FloorUp> floorUp(const DepthRaw& depth, double depthScale, const Intrinsics& k,
                               const Eigen::Vector3d& assumedUp);

inline constexpr double kFloorConeDeg = 10.0;  // a mount measured by hand is a degree or two off
inline constexpr double kFloorTrimDeg = 3.0;   // about the first mean: the floor's normals scatter by ~1-2 degrees
inline constexpr double kFloorMinShare = 0.03;  // of the readings on the grid: a floor band, not a few pixels

}  // namespace sb::odometry
