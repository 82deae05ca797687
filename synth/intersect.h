#pragma once
// Ray-primitive intersection in the primitive's local frame. Rays are o + t d with d NOT normalised: the
// renderer uses d = (x, y, 1) in camera coordinates, so t is directly the depth along the optical axis.
// Each function returns the smallest hit t in (tMin, tMax) or a value >= tMax when there is none.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>

#include "synth/scene.h"

namespace sb::synth {

constexpr float kNoHit = std::numeric_limits<float>::infinity();

// Slab test; a ray starting inside the solid sees nothing of it.
inline float intersectBox(const Eigen::Vector3f& o, const Eigen::Vector3f& d, const Eigen::Vector3f& half,
                          float tMin) {
  float tNear = -kNoHit, tFar = kNoHit;
  for (int a = 0; a < 3; ++a) {
    const float inv = 1.f / d[a];  // +-inf when d[a] == 0: the slab comparisons still hold
    float t0 = (-half[a] - o[a]) * inv;
    float t1 = (half[a] - o[a]) * inv;
    if (std::isnan(t0) || std::isnan(t1)) {  // d[a] == 0 and o[a] exactly on a face
      if (std::abs(o[a]) > half[a]) return kNoHit;
      continue;
    }
    if (t0 > t1) std::swap(t0, t1);
    tNear = std::max(tNear, t0);
    tFar = std::min(tFar, t1);
  }
  if (tNear > tFar || tNear <= tMin) return kNoHit;
  return tNear;
}

// The wall a ray from inside the box leaves through.
inline float intersectRoomBox(const Eigen::Vector3f& o, const Eigen::Vector3f& d, const Eigen::Vector3f& half,
                              float tMin) {
  float tExit = kNoHit;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.f) continue;
    const float bound = d[a] > 0.f ? half[a] : -half[a];
    tExit = std::min(tExit, (bound - o[a]) / d[a]);
  }
  return tExit > tMin ? tExit : kNoHit;
}

// Finite solid cylinder about local y: side then caps.
inline float intersectCylinder(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float radius, float halfHeight,
                               float tMin) {
  float best = kNoHit;
  const float a = d.x() * d.x() + d.z() * d.z();
  if (a > 0.f) {
    const float b = o.x() * d.x() + o.z() * d.z();
    const float c = o.x() * o.x() + o.z() * o.z() - radius * radius;
    const float disc = b * b - a * c;
    if (disc >= 0.f) {
      const float t = (-b - std::sqrt(disc)) / a;  // entering the infinite cylinder
      if (t > tMin && std::abs(o.y() + t * d.y()) <= halfHeight) best = t;
    }
  }
  if (d.y() != 0.f) {
    for (float cap : {-halfHeight, halfHeight}) {
      const float t = (cap - o.y()) / d.y();
      if (t > tMin && t < best) {
        const float x = o.x() + t * d.x(), z = o.z() + t * d.z();
        if (x * x + z * z <= radius * radius) best = t;
      }
    }
  }
  return best;
}

inline float intersectPlane(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float tMin) {
  if (d.z() == 0.f) return kNoHit;
  const float t = -o.z() / d.z();
  return t > tMin ? t : kNoHit;
}

inline float intersectLocal(Shape shape, const Eigen::Vector3f& o, const Eigen::Vector3f& d,
                            const Eigen::Vector3f& half, float tMin) {
  switch (shape) {
    case Shape::Box: return intersectBox(o, d, half, tMin);
    case Shape::Cylinder: return intersectCylinder(o, d, half.x(), half.y(), tMin);
    case Shape::Plane: return intersectPlane(o, d, tMin);
    case Shape::RoomBox: return intersectRoomBox(o, d, half, tMin);
  }
  return kNoHit;
}

// Outward surface normal (local frame, unit) at a local point on the primitive's surface.
inline Eigen::Vector3f normalLocal(Shape shape, const Eigen::Vector3f& p, const Eigen::Vector3f& half) {
  switch (shape) {
    case Shape::Box:
    case Shape::RoomBox: {
      Eigen::Index axis = 0;
      (p.cwiseAbs().cwiseQuotient(half)).maxCoeff(&axis);
      Eigen::Vector3f n = Eigen::Vector3f::Zero();
      n[axis] = p[axis] >= 0.f ? 1.f : -1.f;
      return shape == Shape::RoomBox ? Eigen::Vector3f(-n) : n;  // room walls face inwards
    }
    case Shape::Cylinder: {
      const float radial = std::hypot(p.x(), p.z()) / half.x();
      const float axial = std::abs(p.y()) / half.y();
      if (axial >= radial) return Eigen::Vector3f(0.f, p.y() >= 0.f ? 1.f : -1.f, 0.f);
      return Eigen::Vector3f(p.x(), 0.f, p.z()).normalized();
    }
    case Shape::Plane:
      return Eigen::Vector3f::UnitZ();
  }
  return Eigen::Vector3f::UnitZ();
}

}  // namespace sb::synth
