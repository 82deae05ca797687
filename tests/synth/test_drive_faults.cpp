// The faults of a synthetic drive's base (synth/drive_faults.h): a stall holds the truth while the wheels spin on,
// a carry jumps the truth back while the wheels read nothing, a latency shifts the stamps, a mount error turns the
// camera the odometry reports; wrong wheels change the odometry's steps within their window and nothing else.

#include <catch2/catch.hpp>
#include <cmath>

#include "core/error.h"
#include "core/trajectory.h"
#include "synth/corridor_scene.h"
#include "synth/drive_faults.h"
#include "synth/drive_odometry.h"
#include "tests/synth/exact_odometry.h"
#include "synth/stress_drive.h"
#include "synth/stress_moves.h"

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

// One sample's planar step as the wheels read it: the base's motion from sample k-1 to k (forward, left, turn).
Eigen::Vector3d step(const Trajectory& odometry, size_t k, const Eigen::Isometry3d& mount) {
  const Eigen::Isometry3d d = (odometry[k - 1].T_camera_to_world * mount.inverse()).inverse() *
                              (odometry[k].T_camera_to_world * mount.inverse());
  return {d.translation().x(), d.translation().y(), std::atan2(d.linear()(1, 0), d.linear()(0, 0))};
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

TEST_CASE("wrong wheels change the odometry's steps within their window only, and never the truth",
          "[synth][faults]") {
  const Scene scene = generateCorridor(0);
  const stress::DrivePath path = drivePath(scene, 0);
  const Eigen::Isometry3d mount = path.cameraToBase();
  constexpr double kAtS = 5.0, kForS = 2.0, kEndS = 10.0, kGyroDegps = 20.0, kScale = 2.0;
  const OdometryErrors errors;  // the cheap base's errors and noise: the window must not change their stream
  const Trajectory plain = driveOdometry(path, kEndS, errors, 7);
  for (const WrongWheels kind : {WrongWheels::Reversed, WrongWheels::Zero, WrongWheels::Gyro, WrongWheels::Scaled}) {
    INFO(wrongWheelsName(kind));
    DriveFaults f;
    f.wrong = kind;
    f.wrongAtS = kAtS;
    f.wrongS = kForS;
    f.wrongValue = kind == WrongWheels::Gyro ? kGyroDegps : kScale;
    CHECK_FALSE(f.changesTruth());  // cmd_synth moves the truth only for a fault that changes it
    const DriveClock clock(path, f);
    for (double t = 0.0; t <= kEndS; t += 0.25) CHECK(clock.at(t) == t);
    CHECK(f.describe().find("wheels " + wrongWheelsName(kind)) != std::string::npos);

    const Trajectory wrong = driveOdometry(path, kEndS, errors, 7, 0.0, f);
    REQUIRE(wrong.size() == plain.size());
    size_t inside = 0;
    double drivenM = 0.0;
    for (size_t k = 0; k < plain.size(); ++k) {
      const double t = plain[k].timestamp;
      REQUIRE(wrong[k].timestamp == t);
      if (t <= kAtS) {  // before the window: the very same samples
        CHECK((wrong[k].T_camera_to_world.matrix() - plain[k].T_camera_to_world.matrix()).norm() < 1e-12);
        continue;
      }
      const Eigen::Vector3d p = step(plain, k, mount), w = step(wrong, k, mount);
      if (t > kAtS + kForS) {  // after it: the same steps from where the wrong ones left the odometry
        CHECK((w - p).norm() < 1e-9);
        continue;
      }
      ++inside;
      drivenM += std::abs(p.x());
      const double dt = t - plain[k - 1].timestamp;
      Eigen::Vector3d expected = p;
      if (kind == WrongWheels::Reversed) expected = -p;
      if (kind == WrongWheels::Zero) expected.setZero();
      if (kind == WrongWheels::Gyro) expected.z() += kGyroDegps * stress::kDegToRad * dt;
      if (kind == WrongWheels::Scaled) expected = kScale * p;
      CHECK((w - expected).norm() < 1e-9);
    }
    CHECK(inside == Approx(kForS * errors.rateHz).margin(1.0));
    CHECK(drivenM > 1.0);  // the robot drives through the window, so each kind's steps differ from the plain ones
  }
}

TEST_CASE("--odom-wrong reads KIND,AT,SECONDS[,VALUE] and refuses what it cannot mean", "[synth][faults]") {
  DriveFaults f;
  parseWrongWheelsOption("gyro,5,2", f);
  CHECK(f.wrong == WrongWheels::Gyro);
  CHECK(f.wrongAtS == 5.0);
  CHECK(f.wrongS == 2.0);
  CHECK(f.wrongValue == 20.0);
  parseWrongWheelsOption("scaled,1.5,10,3", f);
  CHECK(f.wrong == WrongWheels::Scaled);
  CHECK(f.wrongValue == 3.0);
  parseWrongWheelsOption("scaled,1.5,10", f);
  CHECK(f.wrongValue == 2.0);
  parseWrongWheelsOption("zero,0,10", f);
  CHECK(f.wrong == WrongWheels::Zero);
  for (const char* bad : {"reversed,1,2,3", "sideways,1,2", "zero,-1,2", "zero,1,0", "zero,1", "zero,a,2",
                          "gyro,1,2,500", "scaled,1,2,nan", "reversed,1,2,", ""}) {
    INFO(bad);
    DriveFaults g;
    CHECK_THROWS_AS(parseWrongWheelsOption(bad, g), Error);
  }
}
