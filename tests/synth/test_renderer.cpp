// Known-answer tests of the ray caster: planes, boxes and cylinders at known poses give analytic depth.

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>

#include "synth/renderer.h"
#include "synth/synth_sequence.h"

using namespace sb;
using namespace sb::synth;

namespace {

SensorModel exactSensor() {
  SensorModel m;
  m.noise = false;
  return m;
}

Scene sceneOf(std::vector<Primitive> prims) {
  Scene s;
  s.name = "test";
  s.primitives = std::move(prims);
  return s;
}

}  // namespace

TEST_CASE("fronto-parallel plane renders its exact distance", "[synth][renderer]") {
  const double distanceM = 2.0;
  const Scene scene = sceneOf({makePlane({0.f, 0.f, static_cast<float>(distanceM)}, {0.f, 0.f, -1.f})});
  const Renderer renderer(scene, iclNuimIntrinsics());
  DepthMeters depth;
  renderer.render(Eigen::Isometry3d::Identity(), exactSensor(), 0, depth);
  DepthRaw raw;
  toRaw(depth, kIclDepthScale, raw);
  REQUIRE(raw.width() == 640);
  REQUIRE(raw.height() == 480);
  for (size_t i = 0; i < raw.size(); ++i) REQUIRE(raw.data()[i] == 10000);  // 2 m at 5000 units/m
}

TEST_CASE("tilted plane seen from a moved camera: per-pixel depth matches the analytic value", "[synth][renderer]") {
  const Intrinsics k = iclNuimIntrinsics();
  // In camera coordinates: plane through (0.1, -0.2, 1.8) with a normal tilted 35 degrees.
  const Eigen::Vector3d pointCam(0.1, -0.2, 1.8);
  const Eigen::Vector3d normalCam =
      (Eigen::AngleAxisd(0.61, Eigen::Vector3d(1.0, 0.4, 0.0).normalized()) * Eigen::Vector3d(0, 0, -1)).normalized();
  Eigen::Isometry3d T_camera_to_world = Eigen::Isometry3d::Identity();
  T_camera_to_world.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, 1.0, -0.3).normalized()).toRotationMatrix();
  T_camera_to_world.translation() = Eigen::Vector3d(0.5, -1.0, 2.0);
  const Eigen::Vector3d pointWorld = T_camera_to_world * pointCam;
  const Eigen::Vector3d normalWorld = T_camera_to_world.linear() * normalCam;
  const Scene scene = sceneOf({makePlane(pointWorld.cast<float>(), normalWorld.cast<float>())});
  const Renderer renderer(scene, k);
  DepthMeters depth;
  renderer.render(T_camera_to_world, exactSensor(), 0, depth);

  int checked = 0;
  for (int y = 0; y < k.height; y += 7) {
    for (int x = 0; x < k.width; x += 5) {
      const Eigen::Vector3d ray((x - k.cx) / k.fx, (y - k.cy) / k.fy, 1.0);
      const double z = normalCam.dot(pointCam) / normalCam.dot(ray);  // n.(z ray) = n.p0
      if (z < 0.4 || z > 4.5) {
        REQUIRE(depth(x, y) == 0.f);  // outside the sensor range
        continue;
      }
      REQUIRE(depth(x, y) == Approx(z).epsilon(2e-6));
      ++checked;
    }
  }
  REQUIRE(checked > 5000);
  // The tilt makes depth vary across the image by more than 0.5 m.
  REQUIRE(std::abs(depth(0, 0) - depth(639, 479)) > 0.5f);
}

TEST_CASE("boxes and cylinders: nearest surface along the optical axis", "[synth][renderer]") {
  Intrinsics k = iclNuimIntrinsics();
  k.width = 65, k.height = 49, k.cx = 32.f, k.cy = 24.f;  // a pixel exactly on the optical axis
  k.fx = k.fy = 60.f;                                     // wide enough to see past the objects
  const Primitive wall = makePlane({0.f, 0.f, 4.f}, {0.f, 0.f, -1.f});
  SECTION("box") {
    // 0.4 m cube centred 1.7 m ahead, rotated 30 degrees about y: the axis meets its front face at
    // 1.7 - 0.2 / cos(30).
    const Primitive box = makeBox({0.f, 0.f, 1.7f}, {0.4f, 0.4f, 0.4f}, 0.5235988f);
    const Scene scene = sceneOf({wall, box});
    const Renderer renderer(scene, k);
    DepthMeters depth;
    renderer.render(Eigen::Isometry3d::Identity(), exactSensor(), 0, depth);
    REQUIRE(depth(32, 24) == Approx(1.7 - 0.2 / std::cos(0.5235988)).epsilon(1e-6));
    REQUIRE(depth(0, 24) == Approx(4.0).epsilon(1e-6));                  // the wall beside it
  }
  SECTION("cylinder") {
    const Primitive cylinder = makeVerticalCylinder({0.f, 0.1f, 2.5f}, 0.3f, 0.2f);  // y down: spans y [-0.1, 0.1]
    const Scene scene = sceneOf({wall, cylinder});
    const Renderer renderer(scene, k);
    DepthMeters depth;
    renderer.render(Eigen::Isometry3d::Identity(), exactSensor(), 0, depth);
    REQUIRE(depth(32, 24) == Approx(2.2).epsilon(1e-6));
    REQUIRE(depth(32, 0) == Approx(4.0).epsilon(1e-6));  // passes above the top: y < -0.11 for z > 2.2
  }
  SECTION("room interior") {
    Primitive room;
    room.shape = Shape::RoomBox;
    room.halfExtents = Eigen::Vector3f(2.f, 1.5f, 3.f);
    const Scene scene = sceneOf({room});
    const Renderer renderer(scene, k);
    DepthMeters depth;
    renderer.render(Eigen::Isometry3d::Identity(), exactSensor(), 0, depth);
    REQUIRE(depth(32, 24) == Approx(3.0).epsilon(1e-6));
  }
}

TEST_CASE("row-parallel and serial rendering agree bit for bit", "[synth][renderer]") {
  const Scene scene = sceneOf({makePlane({0.f, 0.f, 3.f}, {0.2f, 0.1f, -1.f}),
                               makeBox({0.3f, 0.f, 1.5f}, {0.5f, 0.5f, 0.5f}, 0.3f)});
  const Renderer renderer(scene, iclNuimIntrinsics());
  DepthMeters a, b;
  renderer.render(Eigen::Isometry3d::Identity(), SensorModel{}, 7, a, true);
  renderer.render(Eigen::Isometry3d::Identity(), SensorModel{}, 7, b, false);
  REQUIRE(a.pixels() == b.pixels());
}
