#include "synth/corridor_scene.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "synth/rng.h"

namespace sb::synth {

namespace {

constexpr uint64_t kSalt = 0xC0221D02ull;
constexpr float kHalfPi = 1.5707963267948966f;
constexpr float kEndGapM = 0.3f;       // features keep this far from the corridor's ends
constexpr float kDoorHeightM = 2.05f;  // door recesses' height
constexpr float kLightSpacingM[2] = {2.4f, 3.6f};
constexpr float kPipeDropM[2] = {0.12f, 0.3f};  // pipe runs hang this far below the ceiling

// Builds one side of the corridor. `side` is +1 (wall at +x) or -1; positions are metres.
class WallBuilder {
 public:
  WallBuilder(Scene& scene, const CorridorParams& p, float side, Rng& rng)
      : scene_(scene), p_(p), side_(side), rng_(rng), wallX_(side * 0.5f * static_cast<float>(p.widthM)) {}

  void build() {
    const float length = static_cast<float>(p_.lengthM);
    float z = rng_.uniform(kEndGapM, 1.0f);
    while (z < length - kEndGapM) {
      const float room = length - kEndGapM - z;
      float used = 0.f;
      switch (rng_.index(7)) {
        case 0:
          used = door(z, room);
          break;
        case 1:
          used = opening(z, room);
          break;
        case 2:
          used = pillar(z, room);
          break;
        case 3:
        case 4:
          used = cabinet(z, room);
          break;
        case 5:
          used = riser(z, room);
          break;
        default:  // a stretch of plain wall
          used = rng_.uniform(0.5f, 2.0f);
          break;
      }
      z += used + rng_.uniform(0.3f, 1.5f) * static_cast<float>(p_.spacingScale);
    }
    // The wall slabs between the gaps.
    std::sort(gaps_.begin(), gaps_.end());
    float from = 0.f;
    for (const auto& [a, b] : gaps_) {
      slab(from, a, static_cast<float>(p_.heightM));
      from = b;
    }
    slab(from, length, static_cast<float>(p_.heightM));
  }

 private:
  // x of a point `depth` metres behind the wall surface (negative: in front of it).
  float behind(float depth) const { return wallX_ + side_ * depth; }
  float floorY() const { return kCorridorFloorY; }

  // A box spanning x from `d0` to `d1` metres behind the wall, z from z0 to z1, y from `bottom` to `top`
  // metres above the floor.
  void box(float d0, float d1, float z0, float z1, float bottom, float top, const std::string& label) {
    const float x0 = behind(d0), x1 = behind(d1);
    const Eigen::Vector3f centre(0.5f * (x0 + x1), floorY() - 0.5f * (bottom + top), 0.5f * (z0 + z1));
    const Eigen::Vector3f size(std::abs(x1 - x0), top - bottom, z1 - z0);
    scene_.primitives.push_back(makeBox(centre, size, 0.f, label));
  }
  void slab(float z0, float z1, float height) {
    if (z1 - z0 > 1e-3f) box(0.f, static_cast<float>(p_.wallDepthM), z0, z1, 0.f, height, "wall");
  }
  float maxProtrusion() const {
    return 0.5f * static_cast<float>(p_.widthM) - static_cast<float>(p_.clearHalfWidthM);
  }

  float door(float z, float room) {
    const float w = rng_.uniform(0.85f, 1.0f);
    if (w > room) return room;
    const float depth = rng_.uniform(0.1f, 0.2f);
    gaps_.emplace_back(z, z + w);
    box(depth, static_cast<float>(p_.wallDepthM), z, z + w, 0.f, kDoorHeightM, "door");
    box(0.f, static_cast<float>(p_.wallDepthM), z, z + w, kDoorHeightM, static_cast<float>(p_.heightM),
        "lintel");
    return w;
  }
  float opening(float z, float room) {
    const float w = rng_.uniform(1.2f, 2.0f);
    if (w > room) return room;
    gaps_.emplace_back(z, z + w);
    if (rng_.chance(0.5)) {  // something standing in the alcove
      const float d = rng_.uniform(0.3f, 0.6f), bw = rng_.uniform(0.4f, std::min(0.9f, w - 0.2f));
      const float at = z + rng_.uniform(0.1f, w - bw - 0.1f);
      const float back = static_cast<float>(p_.wallDepthM) - 0.05f;
      box(back - d, back, at, at + bw, 0.f, rng_.uniform(0.6f, 1.8f), "alcove.box");
    }
    return w;
  }
  float pillar(float z, float room) {
    const float w = rng_.uniform(0.3f, 0.5f);
    if (w > room) return room;
    const float out = rng_.uniform(0.12f, std::min(0.25f, maxProtrusion()));
    box(-out, 0.f, z, z + w, 0.f, static_cast<float>(p_.heightM), "pillar");
    return w;
  }
  float cabinet(float z, float room) {
    const float w = rng_.uniform(0.6f, 1.2f);
    if (w > room) return room;
    const float out = rng_.uniform(0.3f, std::min(0.4f, maxProtrusion()));
    const float h = rng_.uniform(0.8f, 2.0f);
    box(-out, 0.f, z, z + w, 0.f, h, "cabinet");
    if (rng_.chance(0.4)) {  // a box on top of a low one
      const float bw = rng_.uniform(0.25f, 0.5f * w);
      const float at = z + rng_.uniform(0.f, w - bw);
      if (h < 1.4f)
        box(-rng_.uniform(0.2f, out), 0.f, at, at + bw, h, h + rng_.uniform(0.15f, 0.4f), "cabinet.box");
    }
    return w;
  }
  float riser(float z, float room) {
    const float r = rng_.uniform(0.04f, 0.08f);
    if (2 * r > room) return room;
    const Eigen::Vector3f base(behind(-r - 0.03f), floorY(), z + r);
    scene_.primitives.push_back(makeVerticalCylinder(base, r, static_cast<float>(p_.heightM), "riser"));
    return 2 * r;
  }

  Scene& scene_;
  const CorridorParams& p_;
  float side_;
  Rng& rng_;
  float wallX_;
  std::vector<std::pair<float, float>> gaps_;  // z spans without wall (doors, openings), metres
};

// A horizontal pipe along z, centred at (x, y), from z0 to z1.
Primitive pipe(float x, float y, float z0, float z1, float radius) {
  Primitive p;
  p.shape = Shape::Cylinder;
  p.center = Eigen::Vector3f(x, y, 0.5f * (z0 + z1));
  p.rotation = Eigen::AngleAxisf(kHalfPi, Eigen::Vector3f::UnitX()).toRotationMatrix();
  p.halfExtents = Eigen::Vector3f(radius, 0.5f * (z1 - z0), radius);
  p.label = "pipe";
  return p;
}

}  // namespace

Scene generateCorridor(uint64_t seed, const CorridorParams& p) {
  if (!(p.lengthM >= 4.0 && p.lengthM <= 200.0) || !(p.widthM >= 1.6 && p.widthM <= 4.0) ||
      !(p.heightM >= 2.2 && p.heightM <= 4.0) || !(p.spacingScale >= 0.5 && p.spacingScale <= 20.0))
    throw Error("synth: corridor length " + std::to_string(p.lengthM) + " m, width " +
                std::to_string(p.widthM) + " m, height " + std::to_string(p.heightM) + " m, spacing scale " +
                std::to_string(p.spacingScale) +
                " are out of range; use length 4-200 m, width 1.6-4 m, height 2.2-4 m, spacing scale 0.5-20");
  Scene scene;
  scene.name = kCorridorSceneName;
  scene.seed = seed;
  scene.hasRoom = true;
  const float halfOuter = static_cast<float>(0.5 * p.widthM + p.wallDepthM);
  scene.roomMin = Eigen::Vector3f(-halfOuter, kCorridorFloorY - static_cast<float>(p.heightM), 0.f);
  scene.roomMax = Eigen::Vector3f(halfOuter, kCorridorFloorY, static_cast<float>(p.lengthM));
  Primitive room;
  room.shape = Shape::RoomBox;
  room.center = 0.5f * (scene.roomMin + scene.roomMax);
  room.halfExtents = 0.5f * (scene.roomMax - scene.roomMin);
  room.label = "room";
  scene.primitives.push_back(room);

  Rng rng(seed * 0x2545F4914F6CDD1Dull + kSalt);
  for (float side : {1.f, -1.f}) WallBuilder(scene, p, side, rng).build();

  const float length = static_cast<float>(p.lengthM), ceiling = scene.roomMin.y();
  const float halfWidth = static_cast<float>(0.5 * p.widthM);
  // Pipe runs under the ceiling along a wall: 1-3, 3-10 m long.
  const int runs = 1 + rng.index(3);
  for (int i = 0; i < runs; ++i) {
    const float r = rng.uniform(0.03f, 0.06f), side = rng.chance(0.5) ? 1.f : -1.f;
    const float len = std::min(length - 2 * kEndGapM, rng.uniform(3.f, 10.f));
    const float z0 = rng.uniform(kEndGapM, length - kEndGapM - len);
    const float x = side * (halfWidth - r - rng.uniform(0.03f, 0.2f));
    scene.primitives.push_back(pipe(x, ceiling + rng.uniform(kPipeDropM[0], kPipeDropM[1]), z0, z0 + len, r));
  }
  // Ceiling lights across the middle.
  for (float z = rng.uniform(0.8f, 2.0f); z < length - kEndGapM;
       z += rng.uniform(kLightSpacingM[0], kLightSpacingM[1]) * static_cast<float>(p.spacingScale)) {
    const Eigen::Vector3f size(rng.uniform(0.5f, 1.2f), 0.06f, rng.uniform(0.2f, 0.35f));
    scene.primitives.push_back(
        makeBox(Eigen::Vector3f(0.f, ceiling + 0.5f * size.y(), z), size, 0.f, "light"));
  }
  return scene;
}

}  // namespace sb::synth
