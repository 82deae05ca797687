#include <catch2/catch.hpp>
#include <cmath>

#include "navmap/map_frame.h"

using namespace sb::navmap;

namespace {
constexpr double kDeg = M_PI / 180.0;
}

TEST_CASE("up from a mount: a level camera 1.2 m up", "[navmap]") {
  Eigen::Isometry3d camera = Eigen::Isometry3d::Identity();
  camera.translation() = Eigen::Vector3d(2.0, 1.0, 0.5);
  const MapFrame f = mapFrameFromMount(camera, CameraMount{1.2, 0.0, 0.0});
  // The camera sits 1.2 m above the map's origin; world y is down, world z (the optical axis) is map x.
  CHECK((f.T_world_to_map * camera.translation() - Eigen::Vector3d(0, 0, 1.2)).norm() < 1e-12);
  CHECK((f.T_world_to_map * Eigen::Vector3d(2.0, 2.2, 0.5)).z() == Approx(0.0).margin(1e-12));  // the floor below
  CHECK((f.T_world_to_map * Eigen::Vector3d(2.0, 1.0, 1.5) - Eigen::Vector3d(1, 0, 1.2)).norm() < 1e-12);
  CHECK((f.T_world_to_map * Eigen::Vector3d(1.0, 1.0, 0.5) - Eigen::Vector3d(0, 1, 1.2)).norm() < 1e-12);  // left
}

TEST_CASE("up from a mount: pitched down and rolled", "[navmap]") {
  const Eigen::Isometry3d camera = Eigen::Isometry3d::Identity();
  const MapFrame pitched = mapFrameFromMount(camera, CameraMount{1.0, 10.0, 0.0});
  // A point 2 m along the optical axis lies 2 sin(10 deg) lower than the camera, 2 cos(10 deg) ahead.
  const Eigen::Vector3d ahead = pitched.T_world_to_map * Eigen::Vector3d(0, 0, 2);
  CHECK(ahead.x() == Approx(2 * std::cos(10 * kDeg)));
  CHECK(ahead.y() == Approx(0).margin(1e-12));
  CHECK(ahead.z() == Approx(1.0 - 2 * std::sin(10 * kDeg)));
  const MapFrame rolled = mapFrameFromMount(camera, CameraMount{1.0, 0.0, 5.0});
  // Rolled right side down: the camera's +x (right) points below the horizon.
  const Eigen::Vector3d right = rolled.T_world_to_map * Eigen::Vector3d(1, 0, 0);
  CHECK(right.z() == Approx(1.0 - std::sin(5 * kDeg)));
  CHECK(right.y() == Approx(-std::cos(5 * kDeg)));
}

TEST_CASE("up from odometry: the odometry frame is the map frame", "[navmap]") {
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();
  T_world_camera.rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 1, 0.1).normalized()));
  T_world_camera.translation() = Eigen::Vector3d(2.5, 2.5, 1.5);
  Eigen::Isometry3d T_camera_to_odom = Eigen::Isometry3d::Identity();
  T_camera_to_odom.rotate(Eigen::AngleAxisd(-0.7, Eigen::Vector3d(1, -0.3, 0.4).normalized()));
  T_camera_to_odom.translation() = Eigen::Vector3d(4.0, -1.0, 0.45);
  const MapFrame f = mapFrameFromOdometry(T_world_camera, T_camera_to_odom);
  // The camera's pose in the map frame is its odometry pose.
  CHECK((f.T_world_to_map * T_world_camera).matrix().isApprox(T_camera_to_odom.matrix(), 1e-12));
  CHECK(f.source == "odometry");
}

TEST_CASE("floor fit: a plane 1 m below a camera pitched 8 deg down", "[navmap]") {
  const MapFrame truth = mapFrameFromMount(Eigen::Isometry3d::Identity(), CameraMount{1.0, 8.0, -3.0});
  const Eigen::Isometry3d map_to_camera = truth.T_world_to_map.inverse();
  std::vector<Eigen::Vector3d> points;
  for (double x = 0.8; x < 4.0; x += 0.05)
    for (double y = -1.5; y < 1.5; y += 0.05) points.push_back(map_to_camera * Eigen::Vector3d(x, y, 0.0));
  for (double x = 0.8; x < 4.0; x += 0.1)  // a wall ahead, not the floor
    for (double z = 0.0; z < 2.0; z += 0.1) points.push_back(map_to_camera * Eigen::Vector3d(4.0, x - 2.4, z));
  const auto fit = fitFloor(points);
  REQUIRE(fit);
  CHECK(fit->heightM == Approx(1.0).margin(1e-6));
  CHECK(fit->mount.pitchDeg == Approx(8.0).margin(1e-4));
  CHECK(fit->mount.rollDeg == Approx(-3.0).margin(1e-4));
  CHECK(!fit->describe().empty());
}

TEST_CASE("floor fit: no plane below the camera, no floor", "[navmap]") {
  std::vector<Eigen::Vector3d> wall;
  for (double x = -1; x < 1; x += 0.05)
    for (double y = -1; y < 1; y += 0.05) wall.emplace_back(x, y, 2.0);  // facing the camera
  CHECK(!fitFloor(wall));
}
