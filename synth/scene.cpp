#include "synth/scene.h"

#include <Eigen/Geometry>
#include <cmath>

namespace sb::synth {

std::vector<Eigen::Vector3f> Primitive::corners() const {
  std::vector<Eigen::Vector3f> out;
  out.reserve(8);
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3f local((i & 1) ? halfExtents.x() : -halfExtents.x(),
                                (i & 2) ? halfExtents.y() : -halfExtents.y(),
                                (i & 4) ? halfExtents.z() : -halfExtents.z());
    out.push_back(center + rotation * local);
  }
  return out;
}

bool Primitive::contains(const Eigen::Vector3f& p, float margin) const {
  const Eigen::Vector3f local = rotation.transpose() * (p - center);
  switch (shape) {
    case Shape::Box:
      return (local.cwiseAbs() - halfExtents).maxCoeff() <= margin;
    case Shape::Cylinder:
      return std::hypot(local.x(), local.z()) <= halfExtents.x() + margin &&
             std::abs(local.y()) <= halfExtents.y() + margin;
    case Shape::Plane:
    case Shape::RoomBox:
      return false;
  }
  return false;
}

Primitive makeBox(const Eigen::Vector3f& center, const Eigen::Vector3f& size, float yawRad,
                  const std::string& label) {
  Primitive p;
  p.shape = Shape::Box;
  p.center = center;
  p.rotation = Eigen::AngleAxisf(yawRad, Eigen::Vector3f::UnitY()).toRotationMatrix();
  p.halfExtents = 0.5f * size;
  p.label = label;
  return p;
}

Primitive makeVerticalCylinder(const Eigen::Vector3f& base, float radius, float height, const std::string& label) {
  Primitive p;
  p.shape = Shape::Cylinder;
  p.center = base - Eigen::Vector3f(0.f, 0.5f * height, 0.f);  // y grows downwards
  p.halfExtents = Eigen::Vector3f(radius, 0.5f * height, radius);
  p.label = label;
  return p;
}

Primitive makePlane(const Eigen::Vector3f& point, const Eigen::Vector3f& normal, const std::string& label) {
  Primitive p;
  p.shape = Shape::Plane;
  p.center = point;
  // Any rotation whose local z is the normal.
  p.rotation = Eigen::Quaternionf::FromTwoVectors(Eigen::Vector3f::UnitZ(), normal.normalized()).toRotationMatrix();
  p.label = label;
  return p;
}

bool Scene::insideRoom(const Eigen::Vector3f& p, float margin) const {
  if (!hasRoom) return true;
  return ((p - roomMin).array() >= margin).all() && ((roomMax - p).array() >= margin).all();
}

int Scene::objectContaining(const Eigen::Vector3f& p, float margin) const {
  for (size_t i = 0; i < primitives.size(); ++i) {
    if (primitives[i].bounded() && primitives[i].contains(p, margin)) return static_cast<int>(i);
  }
  return -1;
}

}  // namespace sb::synth
