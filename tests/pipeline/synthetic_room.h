#pragma once
// An analytic test scene for the pipeline tests: the inside of an axis-aligned room (5 planes) with a box
// standing on the floor, rendered to a depth image by per-pixel ray intersection. Everything in the volume
// frame (metres); the camera looks along its +z axis, image y points down (+y in the world is "down").

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/image.h"
#include "core/intrinsics.h"
#include "drivers/frame_source.h"

namespace sb::test {

constexpr double kRoomDepthScale = 10000.0;  // raw units per metre of the rendered frames (0.1 mm steps)

struct Room {
  // A narrow room so that every wall is in view of a camera near (1.5, 1.5, 0.9): all 6 degrees of freedom
  // are constrained.
  double left = 0.9, right = 2.2;     // x of the side walls
  double ceiling = 1.0, floor = 2.0;  // y of ceiling and floor
  double back = 2.7;                  // z of the back wall
  Eigen::Vector3d boxMin{1.0, 1.5, 1.9}, boxMax{1.35, 2.0, 2.3};
};

// Distance along `dir` from `origin` (inside the room) to the first surface.
inline double intersectRoom(const Room& room, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) {
  double t = std::numeric_limits<double>::infinity();
  // Walls: the camera is inside the convex room, so the nearest wall hit is the smallest positive t.
  if (dir.x() > 0) t = std::min(t, (room.right - origin.x()) / dir.x());
  if (dir.x() < 0) t = std::min(t, (room.left - origin.x()) / dir.x());
  if (dir.y() > 0) t = std::min(t, (room.floor - origin.y()) / dir.y());
  if (dir.y() < 0) t = std::min(t, (room.ceiling - origin.y()) / dir.y());
  if (dir.z() > 0) t = std::min(t, (room.back - origin.z()) / dir.z());
  // Box: slab test.
  double t0 = 0, t1 = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (dir(a) == 0) {
      if (origin(a) < room.boxMin(a) || origin(a) > room.boxMax(a)) t1 = -1;
      continue;
    }
    double ta = (room.boxMin(a) - origin(a)) / dir(a), tb = (room.boxMax(a) - origin(a)) / dir(a);
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (t0 <= t1 && t0 > 0) t = std::min(t, t0);
  return t;
}

// Depth frame (raw units of kRoomDepthScale) of the room seen from cameraToWorld.
inline DepthFrame renderRoom(const Room& room, const Eigen::Isometry3d& cameraToWorld, const Intrinsics& k,
                             size_t index = 0) {
  DepthFrame frame;
  frame.index = index;
  frame.timestamp = index / 30.0;
  frame.depth = DepthRaw(k.width, k.height);
  const Eigen::Vector3d origin = cameraToWorld.translation();
  for (int y = 0; y < k.height; ++y)
    for (int x = 0; x < k.width; ++x) {
      const Eigen::Vector3d ray((x - k.cx) / k.fx, (y - k.cy) / k.fy, 1.0);  // z = 1: t is the depth
      const double depth = intersectRoom(room, origin, cameraToWorld.linear() * ray);
      if (std::isfinite(depth) && depth * kRoomDepthScale < 65535)
        frame.depth(x, y) = static_cast<uint16_t>(std::lround(depth * kRoomDepthScale));
    }
  return frame;
}

inline Intrinsics roomIntrinsics(int width = 320, int height = 240) {
  Intrinsics k;
  k.width = width;
  k.height = height;
  k.fx = k.fy = 525.0f * width / 640.0f;
  k.cx = width / 2.0f - 0.5f;
  k.cy = height / 2.0f - 0.5f;
  return k;
}

// A small rigid motion: rotation `degrees` about `axis`, then translation `t`.
inline Eigen::Isometry3d motion(const Eigen::Vector3d& t, double degrees, const Eigen::Vector3d& axis) {
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  m.linear() = Eigen::AngleAxisd(degrees * M_PI / 180.0, axis.normalized()).toRotationMatrix();
  m.translation() = t;
  return m;
}

// The room seen from `pose` with +-3 mm of deterministic noise and a hole every 37th pixel (the OpenCL tests' input).
inline DepthRaw noisyRoom(const Eigen::Isometry3d& pose, const Intrinsics& k) {
  DepthRaw raw = renderRoom(Room{}, pose, k).depth;
  uint32_t state = 12345;
  for (size_t i = 0; i < raw.size(); ++i) {
    state = state * 1664525u + 1013904223u;
    uint16_t& v = raw.pixels()[i];
    if (i % 37 == 0)
      v = 0;
    else if (v > 0)
      v = static_cast<uint16_t>(int(v) + int((state >> 8) % 61) - 30);
  }
  return raw;
}

}  // namespace sb::test
