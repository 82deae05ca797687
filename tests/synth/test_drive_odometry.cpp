// The drive's synthetic wheel odometry (synth/drive_odometry.h): seeded, the stated errors measurable in the
// output, integrated per increment, in the stated frames.

#include <catch2/catch.hpp>
#include <cmath>

#include "core/trajectory.h"
#include "synth/corridor_scene.h"
#include "synth/drive_odometry.h"
#include "tests/synth/exact_odometry.h"
#include "synth/stress_drive.h"

using namespace sb;
using namespace sb::synth;
using sb::synth::test::exactOdometry;

namespace {

double yawOfSample(const TimedPose& p) {  // heading of the camera's forward axis (z) in the odometry plane
  const Eigen::Vector3d f = p.T_camera_to_world.linear().col(2);
  return std::atan2(f.y(), f.x());
}

}  // namespace

TEST_CASE("drive odometry: seeded, at its own rate, not on the frames' stamps", "[synth][odometry]") {
  const Scene scene = generateCorridor(0);
  const stress::DrivePath path = drivePath(scene, 0);
  const OdometryErrors e;
  const Trajectory a = driveOdometry(path, 4.0, e, 0), b = driveOdometry(path, 4.0, e, 0);
  const Trajectory c = driveOdometry(path, 4.0, e, 1);
  REQUIRE(a.size() == b.size());
  REQUIRE(a.size() >= 200);
  CHECK(a.back().timestamp >= 4.0);
  bool differs = false;
  for (size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i].T_camera_to_world.isApprox(b[i].T_camera_to_world, 0.0));
    if (i > 0) CHECK(a[i].timestamp - a[i - 1].timestamp == Approx(0.02));
    if (i < c.size() && !a[i].T_camera_to_world.isApprox(c[i].T_camera_to_world, 1e-12)) differs = true;
    const double frames = a[i].timestamp * 30.0;  // a frame every 1/30 s from 0
    CHECK(std::abs(frames - std::round(frames)) > 1e-3);
  }
  CHECK(differs);
  CHECK(a.front().timestamp > 0.0);
  CHECK(a.front().timestamp < 0.02);
}

TEST_CASE("drive odometry: the camera 1.2 m up, looking along the base's x (REP 103)", "[synth][odometry]") {
  const Scene scene = generateCorridor(3);
  const stress::DrivePath path = drivePath(scene, 3);
  const Trajectory odo = driveOdometry(path, 1.0, exactOdometry(), 3);
  const Eigen::Isometry3d& first = odo.front().T_camera_to_world;
  CHECK(first.translation().z() == Approx(1.2).margin(1e-9));
  CHECK(first.translation().head<2>().norm() < 1e-3);                 // at rest at the start
  CHECK(first.linear().col(2).x() > 0.99);                             // optical z: forward, pitched down
  CHECK(first.linear().col(0).y() == Approx(-1.0).margin(1e-9));       // optical x: right = -y (y is left)
  // With no errors the odometry is the truth: the camera's motion equals the frames' camera motion.
  const Eigen::Isometry3d truth0 = path.cameraToWorld(odo.front().timestamp);
  const Eigen::Isometry3d truth1 = path.cameraToWorld(odo.back().timestamp);
  const Eigen::Isometry3d odoMotion = first.inverse() * odo.back().T_camera_to_world;
  CHECK((odoMotion.translation() - (truth0.inverse() * truth1).translation()).norm() < 0.005);  // vibration
}

TEST_CASE("drive odometry: the stated scale error and yaw bias are measurable", "[synth][odometry]") {
  const Scene scene = generateCorridor(0);
  const stress::DrivePath path = drivePath(scene, 0);
  const double endS = 8.0;  // on the first straight leg
  REQUIRE(path.label(endS) != "turn");
  SECTION("scale: 3% long over the distance driven") {
    OdometryErrors e = exactOdometry();
    e.scale = 0.03;
    const Trajectory odo = driveOdometry(path, endS, e, 0);
    const double driven =
        (odo.back().T_camera_to_world.translation() - odo.front().T_camera_to_world.translation()).norm();
    const double truth = (path.baseToWorld(odo.back().timestamp).translation() -
                          path.baseToWorld(odo.front().timestamp).translation())
                             .norm();
    REQUIRE(truth > 5.0);
    CHECK(driven / truth == Approx(1.03).epsilon(1e-4));
  }
  SECTION("yaw bias: 0.3 deg/s on a straight") {
    OdometryErrors e = exactOdometry();
    e.yawBiasDegps = 0.3;
    const Trajectory odo = driveOdometry(path, endS, e, 0);
    const double turned = (yawOfSample(odo.back()) - yawOfSample(odo.front())) * 180.0 / M_PI;
    CHECK(turned == Approx(0.3 * (odo.back().timestamp - odo.front().timestamp)).epsilon(1e-3));
  }
  SECTION("noise: a random walk that grows with the distance") {
    OdometryErrors e = exactOdometry();
    e.noiseMPerSqrtM = 0.01;
    double sum2 = 0.0;
    const int seeds = 40;
    for (int s = 0; s < seeds; ++s) {
      const Trajectory odo = driveOdometry(path, endS, e, static_cast<uint64_t>(s));
      const Trajectory ref = driveOdometry(path, endS, exactOdometry(), static_cast<uint64_t>(s));
      sum2 += (odo.back().T_camera_to_world.translation() - ref.back().T_camera_to_world.translation())
                  .squaredNorm();
    }
    const double driven = (path.baseToWorld(endS).translation() - path.baseToWorld(0.0).translation()).norm();
    // Two axes, each of variance noise^2 per metre driven.
    CHECK(std::sqrt(sum2 / seeds) == Approx(0.01 * std::sqrt(2.0 * driven)).epsilon(0.3));
  }
}

TEST_CASE("drive odometry: a wheel slip is one step's jump, kept afterwards", "[synth][odometry]") {
  const Scene scene = generateCorridor(0);
  const stress::DrivePath path = drivePath(scene, 0);
  OdometryErrors e = exactOdometry();
  e.slipAtS = 5.0;
  e.slipM = 0.4;
  const Trajectory odo = driveOdometry(path, 7.0, e, 0);
  const Trajectory ref = driveOdometry(path, 7.0, exactOdometry(), 0);
  size_t jumps = 0;
  for (size_t i = 1; i < odo.size(); ++i) {
    const double step =
        (odo[i].T_camera_to_world.translation() - odo[i - 1].T_camera_to_world.translation()).norm();
    if (step > 0.2) {
      ++jumps;
      CHECK(odo[i - 1].timestamp <= 5.0);
      CHECK(odo[i].timestamp > 5.0);
      CHECK(step == Approx(0.4 + (ref[i].T_camera_to_world.translation() -
                                  ref[i - 1].T_camera_to_world.translation())
                                     .norm())
                        .epsilon(1e-6));
    }
  }
  CHECK(jumps == 1);
  CHECK((odo.back().T_camera_to_world.translation() - ref.back().T_camera_to_world.translation()).norm() ==
        Approx(0.4).epsilon(1e-6));
}

TEST_CASE("drive odometry: bad errors are refused naming the value", "[synth][odometry]") {
  OdometryErrors e;
  e.rateHz = 0.0;
  CHECK_THROWS_WITH(e.validate(), Catch::Contains("rate"));
  e = OdometryErrors{};
  e.scale = NAN;
  CHECK_THROWS_WITH(e.validate(), Catch::Contains("scale"));
  CHECK_THAT(OdometryErrors{}.describe(), Catch::Contains("scale error +3%") && Catch::Contains("0.3 deg/s"));
}

TEST_CASE("drive odometry of a part started later: its frame is the base there, its noise its own",
          "[synth][odometry]") {
  const Scene scene = generateCorridor(0);
  const stress::DrivePath path = drivePath(scene, 0);
  const OdometryErrors e;
  const double start = 5.0;  // frame 150
  const Trajectory whole = driveOdometry(path, 8.0, e, 0), part = driveOdometry(path, 8.0, e, 0, start);
  REQUIRE(!part.empty());
  CHECK(part.front().timestamp > start);
  CHECK(part.front().timestamp < start + 0.02);
  CHECK(part.back().timestamp >= 8.0);
  // The base where the part starts is the odometry's origin: the first sample, 0-20 ms later, is within the
  // distance driven in that time (the robot cruises at under 1.5 m/s) of the mount above it.
  const Trajectory exactPart = driveOdometry(path, 8.0, exactOdometry(), 0, start);
  const Eigen::Isometry3d mount = path.cameraToBase();
  CHECK((exactPart.front().T_camera_to_world.translation() - mount.translation()).norm() < 0.03);
  // Exact odometry of the part is the truth's motion since its start.
  const Eigen::Isometry3d startBase = path.baseToWorld(start);
  for (const TimedPose& p : exactPart) {
    const Eigen::Isometry3d truth = startBase.inverse() * path.baseToWorld(p.timestamp) * mount;
    CHECK((p.T_camera_to_world.translation() - truth.translation()).norm() < 1e-6);
  }
  // Fresh noise: not the whole drive's increments.
  CHECK(!part.front().T_camera_to_world.isApprox(whole.front().T_camera_to_world, 1e-9));
}
