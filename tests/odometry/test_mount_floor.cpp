// odometry/floor_up.h and the floor's part of odometry/mount_calibration.h: the base's up read off the floor a
// depth frame shows (a Kinect's quantised depth, a table top at another height, a wall), and the mount's tilt
// learnt from the frames' floors rather than from the turns.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <optional>
#include <string>

#include "odometry/floor_up.h"
#include "odometry/mount_calibration.h"

using namespace sb;
using namespace sb::odometry;

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;
constexpr double kDepthScale = 5000.0;  // raw units per metre

double degreesApart(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) / kDeg;
}

Intrinsics corridorCamera() {
  Intrinsics k;
  k.width = 320;
  k.height = 240;
  k.fx = 240.6f;
  k.fy = 240.f;
  k.cx = 159.5f;
  k.cy = 119.5f;
  return k;
}

// A camera 1.2 m above a floor (world z up, z = 0), looking along +x, pitched down `pitchDeg` and rolled `rollDeg`
// about its optical axis: its rotation camera-to-world.
Eigen::Matrix3d cameraToWorld(double pitchDeg, double rollDeg) {
  Eigen::Matrix3d level;  // optical axes x right, y down, z forward in the world
  level.col(0) = -Eigen::Vector3d::UnitY();
  level.col(1) = -Eigen::Vector3d::UnitZ();
  level.col(2) = Eigen::Vector3d::UnitX();
  return level * Eigen::AngleAxisd(-pitchDeg * kDeg, Eigen::Vector3d::UnitX()).toRotationMatrix() *
         Eigen::AngleAxisd(rollDeg * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

// The depth the camera reads: the floor, a table top 0.75 m high (x 2.5-3.5 m, y -1-0 m), a wall `wallM` ahead;
// `quantised`: a structured-light sensor's disparity steps of 1/8 pixel over a 7.5 cm baseline (6 cm at 3 m).
DepthRaw render(const Eigen::Matrix3d& R, double wallM, bool quantised) {
  const Intrinsics k = corridorCamera();
  const Eigen::Vector3d eye(0.0, 0.0, 1.2);
  DepthRaw depth(k.width, k.height, 0);
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u) {
      const Eigen::Vector3d ray((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);  // its z: the depth per metre along it
      const Eigen::Vector3d w = R * ray;
      double t = 1e9;
      if (w.z() < 0.0) t = std::min(t, -eye.z() / w.z());  // the floor
      if (w.x() > 0.0) t = std::min(t, (wallM - eye.x()) / w.x());
      if (w.z() < 0.0) {  // the table's top
        const double top = (0.75 - eye.z()) / w.z();
        const Eigen::Vector3d p = eye + top * w;
        if (p.x() > 2.5 && p.x() < 3.5 && p.y() > -1.0 && p.y() < 0.0) t = std::min(t, top);
      }
      if (t > 4.5 || t < 0.4) continue;  // the sensor's range
      if (quantised) {
        const double bf = 0.075 * k.fx, disparity = std::round(bf / t * 8.0) / 8.0;
        t = bf / disparity;
      }
      depth(u, v) = static_cast<uint16_t>(std::lround(t * kDepthScale));
    }
  return depth;
}

}  // namespace

TEST_CASE("the floor's up in a depth frame, quantised as a Kinect's, against a mount 2.5 degrees off",
          "[odometry][mount][floor]") {
  const Eigen::Matrix3d R = cameraToWorld(4.0, 1.0);
  const Eigen::Vector3d up = R.transpose() * Eigen::Vector3d::UnitZ();  // the truth, in the camera frame
  const Eigen::Vector3d assumed =
      Eigen::AngleAxisd(1.5 * kDeg, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(2.0 * kDeg, Eigen::Vector3d::UnitX()) * up;
  REQUIRE(degreesApart(assumed, up) == Approx(2.5).margin(0.01));
  const std::optional<FloorUp> exact = floorUp(render(R, 6.0, false), kDepthScale, corridorCamera(), assumed);
  REQUIRE(exact);
  CHECK(degreesApart(exact->up, up) < 0.05);
  // The quantised floor: the mean normal of neighbouring points leans towards the camera (about 0.8 degrees on a
  // corridor's floor); the plane through the points does not.
  const std::optional<FloorUp> kinect = floorUp(render(R, 6.0, true), kDepthScale, corridorCamera(), assumed);
  REQUIRE(kinect);
  CHECK(degreesApart(kinect->up, up) < 0.15);
  CHECK(kinect->share > 0.2);
}

TEST_CASE("a view into a wall shows no floor", "[odometry][mount][floor]") {
  const Eigen::Matrix3d R = cameraToWorld(0.0, 0.0);
  const Eigen::Vector3d up = R.transpose() * Eigen::Vector3d::UnitZ();
  // The wall 1 m ahead: the floor would be seen from 2.3 m on, behind it.
  CHECK_FALSE(floorUp(render(R, 1.0, true), kDepthScale, corridorCamera(), up));
  CHECK_FALSE(floorUp(DepthRaw(320, 240, 0), kDepthScale, corridorCamera(), up));  // a covered lens
}

TEST_CASE("the mount's tilt learnt from the frames' floors, a ramp's frames outvoted, preferred to the turns'",
          "[odometry][mount][floor]") {
  const Eigen::Vector3d up(0.0, -0.995, -0.0998);  // a camera pitched down about 5.7 degrees
  const Eigen::Matrix3d E = (Eigen::AngleAxisd(1.5 * kDeg, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(2.0 * kDeg, Eigen::Vector3d::UnitX())).toRotationMatrix();
  const Eigen::Vector3d assumed = E.transpose() * up.normalized();  // the mount the odometry assumes
  MountCalibration mount;
  for (int i = 0; i < 80; ++i) {
    // Each frame's floor scatters by a tenth of a degree; every fifth frame sees a ramp 4 degrees steep.
    const double wobble = 0.1 * kDeg * std::sin(1.7 * i);
    Eigen::Vector3d floor = Eigen::AngleAxisd(wobble, Eigen::Vector3d::UnitX()) * up.normalized();
    if (i % 5 == 0) floor = Eigen::AngleAxisd(4.0 * kDeg, Eigen::Vector3d::UnitX()) * floor;
    mount.floorSeen(floor, assumed);
    if (i == 20) CHECK(mount.errorDeg() == 0.0);  // fewer than a second of frames: nothing learnt yet
  }
  CHECK(std::string(mount.source()) == "floor");
  CHECK(mount.floorFrames() == 80);
  CHECK(degreesApart(mount.correction() * assumed, up) < 0.1);
  CHECK(mount.errorDeg() == Approx(2.5).margin(0.1));
  CHECK(mount.sigmaDeg(2.0) < 0.2);
  // The turns the view fixes, seen through another (wrong) mount, do not move what the floor taught.
  const Eigen::Matrix3d other = Eigen::AngleAxisd(4.0 * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (int i = 0; i < 60; ++i) {
    const Eigen::Matrix3d view = Eigen::AngleAxisd(3.0 * kDeg, up.normalized()).toRotationMatrix();
    OdometryStep raw;
    raw.delta.linear() = other.transpose() * view * other;
    raw.up = other.transpose() * up.normalized();
    raw.dt = 1.0 / 30;
    mount.learn(view, raw);
  }
  CHECK(degreesApart(mount.correction() * assumed, up) < 0.1);
}

TEST_CASE("floors that do not agree teach nothing", "[odometry][mount][floor]") {
  const Eigen::Vector3d up(0.0, -1.0, 0.0);
  MountCalibration mount;
  for (int i = 0; i < 100; ++i)  // a base rocking by 3 degrees: no one floor
    mount.floorSeen(Eigen::AngleAxisd(3.0 * kDeg * std::sin(0.9 * i), Eigen::Vector3d::UnitZ()) * up, up);
  CHECK(std::string(mount.source()).empty());
  CHECK(mount.errorDeg() == 0.0);
}

TEST_CASE("a mount learnt from the floor, kept by a map store and restored, stands", "[odometry][mount][floor]") {
  const Eigen::Vector3d up(0.0, -1.0, 0.0);
  const Eigen::Vector3d assumed = Eigen::AngleAxisd(2.0 * kDeg, Eigen::Vector3d::UnitX()) * up;
  MountCalibration learnt;
  for (int i = 0; i < 320; ++i) learnt.floorSeen(up, assumed);
  REQUIRE_FALSE(learnt.wantsFloor());
  MountCalibration next;
  next.restore(learnt.state());
  CHECK(std::string(next.source()) == "floor");
  CHECK_FALSE(next.wantsFloor());  // 300 floors were read: no more
  CHECK(degreesApart(next.correction() * assumed, up) < 1e-6);
  CHECK(next.sigmaDeg(2.0) == learnt.sigmaDeg(2.0));
}
