// odometry/odometry_fusion.h on hand-made views: a structure matrix whose eigen-motions are the camera axes
// (basis identity: the twist's translation then rotation, camera at the origin), each with its conditioning.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "odometry/odometry_fusion.h"
#include "tests/odometry/odometry_views.h"

using namespace sb;
using namespace sb::odometry;
using sb::test::view;

namespace {

Eigen::Isometry3d moved(double x, double y, double z) {
  return Eigen::Isometry3d(Eigen::Translation3d(x, y, z));
}

OdometryStep stepOf(const Eigen::Isometry3d& delta, const OdometryConfig& c) {
  OdometryStep s;
  s.delta = delta;
  s.dt = 1.0 / 30;
  s.sigmaM = c.noiseFloorM + c.noisePerM * delta.translation().norm();
  s.sigmaRad = c.noiseFloorRad;
  return s;
}

// fuseWithOdometry for a step from the origin: the view `q`, ICP's pose `tracked`, the odometry's `odometry`
// (its noise from the config).
Fusion fromOrigin(const TrackingQuality& q, const Eigen::Isometry3d& tracked, const Eigen::Isometry3d& odometry,
                  const OdometryConfig& c) {
  return fuseWithOdometry(q, Eigen::Isometry3d::Identity(), tracked, odometry, stepOf(odometry, c), c);
}

// 0.2 s of samples at 50 Hz, the camera driving forward at 1 m/s.
OdometryTrack forwardTrack() {
  OdometryTrack track;
  for (int i = 0; i <= 10; ++i) {
    OdometrySample s;
    s.timestamp = i * 0.02;
    s.T_camera_to_odom = moved(0.0, 0.0, i * 0.02);
    REQUIRE(track.add(s));
  }
  return track;
}

}  // namespace

TEST_CASE("along a motion the view leaves free the odometry wins; along one it fixes, the view",
          "[odometry][fusion]") {
  const OdometryConfig c;
  // A corridor seen lengthwise: forward (tz) is free. The wheels moved 3.5 cm forward; ICP stuck at 0 along z
  // and found 4 mm sideways, which the walls fix.
  const Eigen::Isometry3d predicted = moved(0.0, 0.0, 0.035);
  const Eigen::Isometry3d tracked = moved(0.004, 0.0, 0.0);
  const Fusion f = fromOrigin(view(0.2, {2}), tracked, predicted, c);
  REQUIRE_FALSE(f.rejected);
  CHECK(f.pose.translation().z() == Approx(0.035).margin(1e-6));  // free: the odometry alone
  // Fixed: the view weighs c / (c + lambda); lambda from the noises (config): ICP's weight well over a half.
  const double sigma = c.noiseFloorM + c.noisePerM * 0.035;
  const double lambda = std::pow(c.icpSigmaM / sigma, 2) * c.fullConditioning;
  CHECK(f.pose.translation().x() == Approx(0.004 * 0.2 / (0.2 + lambda)).margin(1e-6));
  CHECK(0.2 / (0.2 + lambda) > 0.7);

  // The same motion in a furnished view (every motion fixed): the tracked pose, nearly.
  const Fusion corner = fromOrigin(view(0.2), moved(0.0, 0.0, 0.033), predicted, c);
  REQUIRE_FALSE(corner.rejected);
  CHECK(corner.pose.translation().z() == Approx(0.033 + 0.002 * lambda / (0.2 + lambda)).margin(1e-6));

  // A blank wall ahead (the view fixes only tz, rx, ry): sliding sideways and turning about z are the wheels'.
  const Eigen::Isometry3d slide = moved(0.02, 0.0, 0.0);
  const Fusion wall = fromOrigin(view(0.2, {0, 1, 5}), Eigen::Isometry3d::Identity(), slide, c);
  CHECK(wall.pose.translation().x() == Approx(0.02).margin(1e-6));
}

TEST_CASE("a wheel slip the view contradicts along the motions it fixes is rejected, not fused",
          "[odometry][fusion]") {
  const OdometryConfig c;
  // The wheels spun: the odometry says 0.4 m forward, the view (which fixes forward here) says 2 cm.
  const Eigen::Isometry3d slipped = moved(0.0, 0.0, 0.4);
  const Eigen::Isometry3d tracked = moved(0.0, 0.0, 0.02);
  const Fusion f = fromOrigin(view(0.2), tracked, slipped, c);
  CHECK(f.rejected);
  CHECK(f.disagreementM == Approx(0.38).margin(1e-6));
  CHECK(f.pose.isApprox(tracked));
  CHECK_THAT(f.why, Catch::Contains("0.380 m"));
  // Along a motion the view leaves free, the view cannot contradict it: fused (the wheels' word is all there is).
  const Fusion corridor = fromOrigin(view(0.2, {2}), tracked, slipped, c);
  CHECK_FALSE(corridor.rejected);
  // A rotation slip: the wheels say 10 degrees, the view (fixing every rotation) says none.
  const Eigen::Isometry3d turned(Eigen::AngleAxisd(10 * M_PI / 180, Eigen::Vector3d::UnitY()));
  const Fusion turn = fromOrigin(view(0.2), Eigen::Isometry3d::Identity(), turned, c);
  CHECK(turn.rejected);
  // Within the noise: fused.
  const Fusion small = fromOrigin(view(0.2), moved(0.0, 0.0, 0.036), moved(0.0, 0.0, 0.035), c);
  CHECK_FALSE(small.rejected);
  // No structure known: the tracked pose, not judged.
  CHECK(fromOrigin(TrackingQuality{}, tracked, slipped, c).pose.isApprox(tracked));
}

TEST_CASE("of a view and wheels that disagree, the one that breaks inertia is wrong", "[odometry][physics]") {
  const OdometryConfig c;
  const Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
  const double dt = 1.0 / 30;
  Velocity creeping;  // the robot setting off
  creeping.linear = Eigen::Vector3d(0, 0, 0.2);
  // The view ran away 0.12 m in one frame, the wheels went on at 7 mm: the view is wrong.
  CHECK_THAT(viewBreaksInertia(start, moved(0, 0, 0.12), moved(0, 0, 0.007), dt, creeping, c.slipFloorM),
             Catch::Contains("the view is wrong") && Catch::Contains("0.113 m"));
  // A runaway within every limit of the platform (2.1 m/s, 57 m/s^2): still the view's, against the wheels.
  CHECK_FALSE(viewBreaksInertia(start, moved(0, 0, 0.071), moved(0, 0, 0.008), dt, creeping, c.slipFloorM).empty());
  // A wheel slip: the wheels jump 0.4 m, the view goes on at 7 mm: not the view's.
  CHECK(viewBreaksInertia(start, moved(0, 0, 0.007), moved(0, 0, 0.4), dt, creeping, c.slipFloorM).empty());
  // Sideways: the view slid 5 cm to the side while the wheels kept the heading.
  CHECK_FALSE(
      viewBreaksInertia(start, moved(0.05, 0, 0.007), moved(0, 0, 0.007), dt, creeping, c.slipFloorM).empty());
  // Both near the last velocity (a rotation disagreement): within tracking's own noise, not judged here.
  CHECK(viewBreaksInertia(start, moved(0, 0, 0.012), moved(0, 0, 0.005), dt, creeping, c.slipFloorM).empty());
  // Without a last velocity or time, not judged.
  CHECK(viewBreaksInertia(start, moved(0, 0, 0.3), moved(0, 0, 0.007), dt, std::nullopt, c.slipFloorM).empty());
  CHECK(viewBreaksInertia(start, moved(0, 0, 0.3), moved(0, 0, 0.007), 0.0, creeping, c.slipFloorM).empty());
}

TEST_CASE("a body keeps its turn rate: a view that swings against it in one frame is wrong", "[odometry][physics]") {
  const OdometryConfig c;
  const double dt = 1.0 / 30;
  const auto yawed = [](double deg, double z) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(deg * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(0, 0, z);
    return T;
  };
  const Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
  // An in-place U-turn at 60 deg/s (2 deg a frame): the wheels turn on, the view facing the end wall swings 9 deg.
  const Velocity turning = velocityBetween(yawed(-2, 0), start, dt);
  CHECK(turning.angular.norm() == Approx(60 * M_PI / 180).epsilon(1e-9));
  CHECK_THAT(viewBreaksInertia(start, yawed(9, 0.005), yawed(2, 0), dt, turning, c.slipFloorM),
             Catch::Contains("the view turns 7.00 deg from the last turn rate") && Catch::Contains("0.00 deg"));
  // A gyro running away (the wheels turn 2 deg more than the turn goes on), the view keeps the turn: not the view's.
  CHECK(viewBreaksInertia(start, yawed(2, 0), yawed(4, 0), dt, turning, c.slipFloorM).empty());
  // The view stops turning within tracking's noise of a frame (1 deg from the turn's 2): not judged.
  CHECK(viewBreaksInertia(start, yawed(1, 0), yawed(2, 0), dt, turning, c.slipFloorM).empty());
  // The wheels jumped 0.4 m as the view swung: the wheels' jump is the larger departure, the turn is not judged.
  CHECK(viewBreaksInertia(start, yawed(9, 0), yawed(2, 0.4), dt, turning, c.slipFloorM).empty());
}

TEST_CASE("a motion the platform cannot make is named; one it can is not", "[odometry][physics]") {
  const OdometryConfig c;  // 3 m/s, 100 m/s^2, 400 deg/s
  const Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
  const double dt = 1.0 / 30;
  CHECK(implausibleMotion(c, start, moved(0.0, 0.0, 0.035), dt, Eigen::Vector3d(0, 0, 1.0)).empty());
  // A runaway: 0.3 m in one frame (9 m/s).
  CHECK_THAT(implausibleMotion(c, start, moved(0.0, 0.0, 0.3), dt, Eigen::Vector3d(0, 0, 1.0)),
             Catch::Contains("m/s") && Catch::Contains("beyond"));
  // A spliced far frame: 5 m away.
  CHECK_FALSE(implausibleMotion(c, start, moved(5.0, 0.0, 0.0), dt, std::nullopt).empty());
  // A stuck frame caught up at 1 m/s (0 -> 2 m/s in a frame, 60 m/s^2): the estimate's error, not a runaway.
  CHECK(implausibleMotion(c, start, moved(0.0, 0.0, 0.067), dt, Eigen::Vector3d::Zero()).empty());
  // Reversing at 2.5 m/s within one frame: 150 m/s^2.
  CHECK_THAT(implausibleMotion(c, start, moved(0.0, 0.0, -0.083), dt, Eigen::Vector3d(0, 0, 2.5)),
             Catch::Contains("accelerated"));
  // Turning 30 degrees in one frame: 900 deg/s.
  const Eigen::Isometry3d spun(Eigen::AngleAxisd(30 * M_PI / 180, Eigen::Vector3d::UnitY()));
  CHECK_THAT(implausibleMotion(c, start, spun, dt, std::nullopt), Catch::Contains("deg/s"));
  // No time between the frames (or stamps out of order): not judged.
  CHECK(implausibleMotion(c, start, moved(5.0, 0.0, 0.0), 0.0, std::nullopt).empty());
}

TEST_CASE("the odometry's step between two frames, with its noise", "[odometry][fusion]") {
  OdometryConfig c;
  const OdometryTrack track = forwardTrack();
  std::string why;
  const auto step = stepBetween(track, 0.03, 0.0633, c, why);
  REQUIRE(step);
  CHECK(step->delta.translation().z() == Approx(0.0333).margin(1e-9));
  CHECK(step->sigmaM == Approx(c.noiseFloorM + c.noisePerM * 0.0333).margin(1e-9));
  CHECK_FALSE(stepBetween(track, 0.1, 0.5, c, why));  // past the newest sample by more than the bound
  CHECK_THAT(why, Catch::Contains("no odometry at 0.500"));
}

TEST_CASE("after frames skipped on the wheels, the prediction carries the whole interval's noise", "[odometry][fusion]") {
  const OdometryConfig c;
  const OdometryTrack track = forwardTrack();
  std::string why;
  // The tracked frame at 0.1 s; the view last fixed the pose at 0.0 s, two frames skipped between.
  auto step = stepBetween(track, 1.0 / 15, 0.1, c, why);
  const auto since = stepBetween(track, 0.0, 0.1, c, why);
  REQUIRE(step);
  REQUIRE(since);
  const OdometryStep one = *step;
  widenNoise(*step, *since);
  CHECK(step->sigmaM == Approx(c.noiseFloorM + c.noisePerM * 0.1).margin(1e-9));
  CHECK(step->sigmaRad == Approx(since->sigmaRad).margin(1e-12));
  CHECK(step->delta.isApprox(one.delta));  // the motion is the step's: only its noise grows
  // The consequence: along a motion the view fixes, a view 4 mm off the wheels' prediction now weighs more.
  const Eigen::Isometry3d predicted = moved(0.0, 0.0, 0.0333), tracked = moved(0.004, 0.0, 0.0333);
  const Fusion narrow = fuseWithOdometry(view(0.2, {2}), Eigen::Isometry3d::Identity(), tracked, predicted, one, c);
  const Fusion wide = fuseWithOdometry(view(0.2, {2}), Eigen::Isometry3d::Identity(), tracked, predicted, *step, c);
  REQUIRE_FALSE(narrow.rejected);
  REQUIRE_FALSE(wide.rejected);
  CHECK(wide.pose.translation().x() > narrow.pose.translation().x() + 0.0003);
  CHECK(wide.pose.translation().x() < 0.004);
  // A widened step never narrows: the interval's noise only counts when it is the larger.
  OdometryStep big = one;
  big.sigmaM = 1.0;
  widenNoise(big, *since);
  CHECK(big.sigmaM == 1.0);
}

TEST_CASE("the odometry's tilt is absolute: a fused pose is drawn to it", "[odometry][fusion]") {
  const OdometryConfig c;
  const Eigen::Vector3d up(0.0, -1.0, 0.0);  // the camera's y points down: up is -y
  // The odometry's camera: level, heading 3 degrees off the world's z, 5 cm higher than the prediction (the last
  // fused pose moved by the wheels, at the origin as the hand-made view's basis has it), which drifted 2 degrees
  // nose down about the camera's x.
  const Eigen::Matrix3d heading = Eigen::AngleAxisd(3.0 / 57.2957795, up).toRotationMatrix();
  Eigen::Isometry3d odometry = moved(0.0, -0.05, 0.0);
  odometry.linear() = heading;
  Eigen::Isometry3d predicted = Eigen::Isometry3d::Identity();
  predicted.linear() = heading * Eigen::AngleAxisd(-2.0 / 57.2957795, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const auto tiltDeg = [&](const Eigen::Isometry3d& p) {
    return std::acos(std::clamp((p.linear().transpose() * up).dot(Eigen::Vector3d(0.0, -1.0, 0.0)), -1.0, 1.0)) *
           57.2957795;
  };
  const auto headingOf = [](const Eigen::Isometry3d& p) {
    const Eigen::Vector3d ahead = p.linear() * Eigen::Vector3d::UnitZ();
    return std::atan2(ahead.x(), ahead.z());
  };
  const Eigen::Isometry3d whole = levelled(predicted, odometry, up);
  CHECK(tiltDeg(predicted) == Approx(2.0));
  CHECK(tiltDeg(whole) == Approx(0.0).margin(1e-6));
  CHECK(whole.translation().isApprox(predicted.translation(), 1e-12));  // the position and the heading stay
  CHECK(headingOf(whole) == Approx(headingOf(odometry)));

  // In the fusion: a view that leaves the pitch free and a standing robot (a zero step). With the level the fused
  // pose turns toward it by the share its information earns against the step's; without it, not at all.
  const OdometryStep step = stepOf(Eigen::Isometry3d::Identity(), c);
  const TrackingQuality q = view(0.2, {3});
  const Fusion plain = fuseWithOdometry(q, predicted, predicted, predicted, step, c);
  const Fusion level = fuseWithOdometry(q, predicted, predicted, predicted, step, c, Level{odometry, up});
  REQUIRE_FALSE(level.rejected);
  CHECK(plain.pose.isApprox(predicted, 1e-9));
  const double share = 1.0 / (1.0 + std::pow(c.tiltSigmaDeg / 57.2957795 / step.sigmaRad, 2));
  CHECK(tiltDeg(level.pose) == Approx(2.0 * (1.0 - share)).epsilon(0.02));
  CHECK(level.pose.translation().isApprox(predicted.translation(), 1e-6));
  OdometryConfig off = c;
  off.tiltSigmaDeg = 0.0;
  CHECK(fuseWithOdometry(q, predicted, predicted, predicted, step, off, Level{odometry, up}).pose.isApprox(predicted, 1e-9));

  // After a U-turn from the frame the tilt was anchored at, a mount 2 degrees off tilts the odometry's camera by
  // 4 degrees: its tilt's sigma grows to hypot(0.5, 2 * 2) degrees, and the fused pose turns toward it by the share
  // that earns. Held to 0.5 degrees it took most of a wrong tilt (a held-out mount drive: the map rolled 4.5
  // degrees and the way back climbed 1.2 m).
  CHECK(levelSigmaRad(0.5, 2.0, 0.0) * 57.2957795 == Approx(0.5));
  CHECK(levelSigmaRad(0.5, 2.0, M_PI) * 57.2957795 == Approx(std::hypot(0.5, 4.0)));
  CHECK(levelSigmaRad(0.5, 2.0, M_PI / 3) * 57.2957795 == Approx(std::hypot(0.5, 2.0)));  // chord 1 at 60 degrees
  const double turnedSigma = levelSigmaRad(c.tiltSigmaDeg, c.mountSigmaDeg, M_PI);
  const Fusion uTurn = fuseWithOdometry(q, predicted, predicted, predicted, step, c,
                                        Level{odometry, up, turnedSigma});
  const double turnedShare = 1.0 / (1.0 + std::pow(turnedSigma / step.sigmaRad, 2));
  CHECK(tiltDeg(uTurn.pose) == Approx(2.0 * (1.0 - turnedShare)).epsilon(0.02));
  CHECK(turnedShare < 0.1 * share);
}

TEST_CASE("a wheel bias held against a view of the map: the previous pose's covariance bounds the standing error",
          "[odometry][fusion]") {
  // The camera stands still, ICP finds it where it is (the map is right), and the wheels turn it 0.01 deg a frame
  // (a 0.3 deg/s gyro drift at 30 Hz). Each frame's fusion starts from the last fused pose. Counting the previous
  // pose as exact, the view's share of each frame stays K and the error stands at about b (1 - K) / K; with its
  // covariance carried (a Kalman filter's prior), the share grows to the filter's steady state.
  const OdometryConfig c;
  const double biasRad = 0.01 * M_PI / 180.0;
  const TrackingQuality q = view(0.01);  // a view that fixes every motion, weakly (a corridor's heading)
  auto standing = [&](const Eigen::Vector3d& axis, bool carry) {
    const Eigen::Isometry3d turn(Eigen::AngleAxisd(biasRad, axis));
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    std::optional<Matrix6> covariance;
    for (int i = 0; i < 600; ++i) {
      OdometryStep step = stepOf(turn, c);
      const Fusion f = fuseWithOdometry(q, pose, Eigen::Isometry3d::Identity(), pose * turn, step, c, std::nullopt,
                                        carry ? covariance : std::nullopt);
      REQUIRE_FALSE(f.rejected);
      REQUIRE(f.covariance);
      pose = f.pose;
      covariance = f.covariance;
    }
    return Eigen::AngleAxisd(pose.linear()).angle() / biasRad;  // in frames of bias
  };
  const Eigen::Vector3d up = OdometryStep{}.up, across = up.unitOrthogonal();
  const double exact = standing(up, false), carried = standing(up, true);
  INFO("standing heading error in frames of bias: previous pose exact " << exact << ", covariance carried " << carried);
  // Here K is about 1/80: counted exact, 80 frames of bias (0.8 deg); carried, the filter's share is about
  // sqrt(K) (its prior grows until the two weigh so), about 9 frames (0.09 deg).
  CHECK(exact > 40.0);
  CHECK(carried < exact / 5.0);
  // A tilt bias likewise (the odometry's absolute tilt is not given here).
  CHECK(standing(across, true) < standing(across, false) / 5.0);
}
