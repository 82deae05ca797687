#pragma once
// Procedural indoor scenes made of analytic primitives: boxes (axis-aligned or rotated), finite cylinders,
// infinite planes, and the room itself (a box seen from inside).
//
// World frame: the ICL-NUIM trajectory frame. Handheld cameras in those trajectories keep their image "up"
// (camera -y) along world -y, so gravity points along world +y: the floor is the plane y = floorY (largest y)
// and the ceiling is at smaller y. Metres throughout.

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace sb::synth {

enum class Shape {
  Box,       // solid box: local |x|,|y|,|z| <= halfExtents
  Cylinder,  // solid cylinder: local x^2 + z^2 <= radius^2 (halfExtents.x), |y| <= halfExtents.y
  Plane,     // infinite two-sided plane local z = 0 (halfExtents unused)
  RoomBox,   // the inside surface of a box: rays from inside hit the wall they leave through
};

struct Primitive {
  Shape shape = Shape::Box;
  Eigen::Vector3f center = Eigen::Vector3f::Zero();          // metres, world
  Eigen::Matrix3f rotation = Eigen::Matrix3f::Identity();    // world-from-local
  Eigen::Vector3f halfExtents = Eigen::Vector3f::Zero();     // metres, local (see Shape)
  std::string label;                                          // e.g. "sofa.seat", for debugging

  bool bounded() const { return shape == Shape::Box || shape == Shape::Cylinder; }
  // The 8 corners of the local bounding box, in world coordinates (bounded shapes only).
  std::vector<Eigen::Vector3f> corners() const;
  // True when `p` (world) is inside the solid, grown by `margin` metres (bounded shapes only).
  bool contains(const Eigen::Vector3f& p, float margin = 0.f) const;
};

Primitive makeBox(const Eigen::Vector3f& center, const Eigen::Vector3f& size, float yawRad = 0.f,
                  const std::string& label = "box");
// A vertical cylinder standing with its base centre at `base` (world; y grows downwards, so the top is at
// base.y - height).
Primitive makeVerticalCylinder(const Eigen::Vector3f& base, float radius, float height,
                               const std::string& label = "cylinder");
// The plane through `point` with normal `normal` (need not be unit).
Primitive makePlane(const Eigen::Vector3f& point, const Eigen::Vector3f& normal, const std::string& label = "plane");

// A stretch of wall the generator keeps free of furniture and panels over the whole room height, and the floor
// in front of it clear up to clearDepthM (plan view: x, z).
struct BlankWall {
  Eigen::Vector2f from = Eigen::Vector2f::Zero(), to = Eigen::Vector2f::Zero();  // ends on the wall, metres
  Eigen::Vector2f inward = Eigen::Vector2f::Zero();  // unit normal into the room
  float clearDepthM = 0.f;                            // metres from the wall kept free of furniture

  Eigen::Vector2f middle() const { return 0.5f * (from + to); }
  float length() const { return (to - from).norm(); }
};

struct Scene {
  std::string name;  // "livingroom", "office", or a test scene
  uint64_t seed = 0;
  // The room interior, axis-aligned, world. Empty scenes (tests) may have no room (hasRoom false).
  bool hasRoom = false;
  Eigen::Vector3f roomMin = Eigen::Vector3f::Zero();
  Eigen::Vector3f roomMax = Eigen::Vector3f::Zero();
  std::vector<Primitive> primitives;  // includes the RoomBox when hasRoom
  std::vector<BlankWall> blankWalls;  // generated rooms: one per wall

  // Inside the room's walls by at least `margin` metres (true when there is no room).
  bool insideRoom(const Eigen::Vector3f& p, float margin = 0.f) const;
  // Index of a bounded primitive containing `p` (grown by margin), or -1.
  int objectContaining(const Eigen::Vector3f& p, float margin = 0.f) const;
};

}  // namespace sb::synth
