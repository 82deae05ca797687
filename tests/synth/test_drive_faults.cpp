// The faults of a synthetic drive's base (synth/drive_faults.h): a stall holds the truth while the wheels spin on,
// a carry jumps the truth back while the wheels read nothing, a latency shifts the stamps, a mount error turns the
// camera the odometry reports.

#include <catch2/catch.hpp>
#include <cmath>

#include "core/error.h"
#include "core/trajectory.h"
#include "synth/corridor_scene.h"
#include "synth/drive_faults.h"
#include "synth/drive_odometry.h"
#include "tests/synth/exact_odometry.h"
#include "synth/stress_drive.h"

using namespace sb;
using namespace sb::synth;
using sb::synth::test::exactOdometry;

namespace {

// The odometry's camera position at the sample nearest `t`.
Eigen::Vector3d odometryAt(const Trajectory& odometry, double t) {
  const TimedPose* best = &odometry.front();
  for (const TimedPose& p : odometry)
    if (std::abs(p.timestamp - t) < std::abs(best->timestamp - t)) best = &p;
  return best->T_camera_to_world.translation();
}

}  // namespace

TEST_CASE("a stall holds the truth while the wheels read on; a carry jumps it back while they read nothing",
          "[synth][faults]") {
  const Scene scene = generateCorridor(0);
  const stress::DrivePath path = drivePath(scene, 0);
  DriveFaults stall;
  stall.stallAtS = 5.0;
  stall.stallS = 2.0;
  stall.stallSpeedMps = 1.0;
  const DriveClock clock(path, stall);
  CHECK(clock.at(4.0) == 4.0);
  CHECK(clock.at(6.0) == Approx(5.0));
  CHECK(clock.at(8.0) == Approx(6.0));
  CHECK(clock.stalled(6.0));
  CHECK_FALSE(clock.stalled(7.5));
  const Trajectory wheels = driveOdometry(path, 8.0, exactOdometry(), 0, 0.0, stall);
  // The wheels report about 1 m/s through the stall while the truth stands.
  CHECK((odometryAt(wheels, 6.9) - odometryAt(wheels, 5.1)).norm() == Approx(1.8).margin(0.1));
  CHECK((path.cameraToWorld(clock.at(6.9)).translation() - path.cameraToWorld(clock.at(5.1)).translation()).norm() <
        1e-9);

  DriveFaults carry;
  carry.carriedAtS = 10.0;
  carry.carriedBackM = 4.0;
  const DriveClock carried(path, carry);
  const double back = (path.baseToWorld(10.0).translation() - path.baseToWorld(carried.at(10.0)).translation()).norm();
  CHECK(back == Approx(4.0).margin(0.05));
  CHECK(carried.carriedBetween(9.99, 10.01));
  const Trajectory still = driveOdometry(path, 10.5, exactOdometry(), 0, 0.0, carry);
  const Trajectory plain = driveOdometry(path, 10.5, exactOdometry(), 0);
  // Across the carry the wheels read one sample's worth of nothing; after it they read the drive on.
  const double carriedStep = (odometryAt(still, 10.01) - odometryAt(still, 9.99)).norm();
  const double drivenStep = (odometryAt(plain, 10.01) - odometryAt(plain, 9.99)).norm();
  CHECK(carriedStep < 0.5 * drivenStep);
}

TEST_CASE("a latency shifts the stamps; a mount error turns the reported camera; bad values are refused",
          "[synth][faults]") {
  const Scene scene = generateCorridor(0);
  const stress::DrivePath path = drivePath(scene, 0);
  DriveFaults late;
  late.latencyS = 0.04;
  const Trajectory a = driveOdometry(path, 3.0, exactOdometry(), 0);
  const Trajectory b = driveOdometry(path, 3.0, exactOdometry(), 0, 0.0, late);
  REQUIRE(a.size() == b.size());
  CHECK(b[10].timestamp - a[10].timestamp == Approx(0.04));
  CHECK((b[10].T_camera_to_world.matrix() - a[10].T_camera_to_world.matrix()).norm() < 1e-12);

  DriveFaults mount;
  mount.mountError = {0.0, 2.0, 0.0, 0.0, 0.0, 0.0};
  const Trajectory m = driveOdometry(path, 3.0, exactOdometry(), 0, 0.0, mount);
  const double angle = Eigen::AngleAxisd(a[10].T_camera_to_world.linear().transpose() * m[10].T_camera_to_world.linear())
                           .angle() * 180.0 / 3.14159265358979323846;
  CHECK(angle == Approx(2.0).margin(1e-6));
  CHECK(mount.describe().find("mount off by") != std::string::npos);

  DriveFaults bad;
  bad.stallS = -1.0;
  CHECK_THROWS_AS(bad.validate(), Error);
  bad = DriveFaults{};
  bad.stallAtS = 1.0;
  bad.carriedAtS = 2.0;
  CHECK_THROWS_AS(bad.validate(), Error);
}
