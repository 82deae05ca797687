// odometry/wheel_faults.h and odometry/mount_calibration.h: the evidence of a disagreement between the wheels
// and the view, decided over a window and not by one frame; the map's agreement a view must keep; the mount's
// error from the axes of the turns; the odometry's clock from the changes of turn rate.
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <utility>

#include "odometry/motion_model.h"
#include "odometry/mount_calibration.h"
#include "odometry/time_offset.h"
#include "odometry/wheel_faults.h"

using namespace sb::odometry;

namespace {
constexpr double kFrameS = 1.0 / 30;
constexpr double kDeg = 3.14159265358979323846 / 180.0;
}  // namespace

TEST_CASE("one frame's disagreement is not a verdict; a disagreement that lasts is", "[odometry][faults]") {
  FaultWatch watch(0.3, 0.5);
  watch.wheelsContradicted(0.0);
  CHECK(watch.fault() == WheelFault::disputed);
  watch.agreed(kFrameS);
  watch.agreed(2 * kFrameS);
  CHECK(watch.fault() == WheelFault::disputed);  // three frames of agreement end a dispute, not two
  watch.agreed(3 * kFrameS);
  CHECK(watch.fault() == WheelFault::none);

  // A stall: the view holds the map frame after frame while the wheels run on.
  double t = 1.0;
  watch.wheelsContradicted(t);
  for (int i = 1; i * kFrameS < 0.3 - 1e-9; ++i) {
    watch.wheelsContradicted(t + i * kFrameS);
    CHECK(watch.fault() == WheelFault::disputed);
  }
  watch.wheelsContradicted(t + 0.31);
  CHECK(watch.fault() == WheelFault::slipping);
  CHECK_FALSE(watch.why().empty());
  // Slipping ends only after calm_s of agreement.
  t += 1.0;
  for (int i = 0; i < 10; ++i) watch.agreed(t + i * kFrameS);
  CHECK(watch.fault() == WheelFault::slipping);
  watch.agreed(t + 0.6);
  CHECK(watch.fault() == WheelFault::none);
}

TEST_CASE("agreement ends a dispute only in frames in a row: a discarded view between them breaks the run",
          "[odometry][faults]") {
  // Wheels reading zero while the robot drove on (a held-out drive): agree, a view discarded as a motion the platform
  // cannot make, agree, agree, and the dispute ended on a `good` frame 0.62 m off.
  FaultWatch watch(0.3, 0.5);
  watch.wheelsContradicted(0.0);
  watch.agreed(kFrameS);
  watch.interrupt();  // the view disagreed with the wheels and was discarded
  watch.agreed(3 * kFrameS);
  watch.agreed(4 * kFrameS);
  CHECK(watch.fault() == WheelFault::disputed);
  watch.agreed(5 * kFrameS);
  CHECK(watch.fault() == WheelFault::none);
}

TEST_CASE("a view that does not fit the map near the wheels' pose for the decision time is a kidnap",
          "[odometry][faults]") {
  // Decided by the window, not by the dead-reckoning budget: a robot set down 8 m back drove on its wheels' pose
  // into a stretch the map did not hold, the evidence stopped there, the dispute was dropped and the view was fused
  // at the wheels' pose (a held-out drive: 669 `good` frames 8 m off; decided by the window, relocalised 0.9 s
  // after the set-down).
  FaultWatch watch(0.3, 0.5);
  CHECK_FALSE(watch.concludeKidnapped());  // no dispute: a covered lens's dead reckoning ending is not a kidnap
  for (int i = 0; i < 9; ++i) {
    watch.viewContradicted(i * kFrameS);
    CHECK(watch.fault() == WheelFault::disputed);  // 0.27 s: not yet
  }
  watch.viewContradicted(0.31);
  CHECK(watch.fault() == WheelFault::kidnapped);
  CHECK_FALSE(watch.why().empty());
  watch.reset();
  CHECK(watch.fault() == WheelFault::none);
  // Within the decision time, a dead reckoning that ends its budget on that evidence ends it too.
  for (int i = 0; i < 5; ++i) watch.viewContradicted(i * kFrameS);
  CHECK(watch.fault() == WheelFault::disputed);
  CHECK(watch.concludeKidnapped());
  CHECK(watch.fault() == WheelFault::kidnapped);
  watch.reset();

  // Mixed evidence: the side with more frames wins only when the window is over.
  for (int i = 0; i < 6; ++i) watch.viewContradicted(i * kFrameS);
  for (int i = 6; i < 20; ++i) watch.wheelsContradicted(i * kFrameS);
  CHECK(watch.fault() == WheelFault::slipping);
}

TEST_CASE("a stall: the view's correction of the wheels keeps growing; a view's jump does not", "[odometry][faults]") {
  FaultWatch stall(0.3, 0.5), jump(0.3, 0.5);
  CHECK_FALSE(stall.diverging(0.0, 0.033));
  CHECK_FALSE(stall.diverging(kFrameS, 0.066));
  CHECK(stall.diverging(2 * kFrameS, 0.099));  // tripled over three rising frames: the wheels run away
  CHECK(stall.fault() == WheelFault::disputed);
  // A view that slid to a look-alike, discarded each frame from the wheels' prediction: bounded corrections.
  const double corrections[] = {0.035, 0.042, 0.051, 0.056, 0.050, 0.052};
  for (int i = 0; i < 6; ++i) CHECK_FALSE(jump.diverging(i * kFrameS, corrections[i]));
  // Rising corrections with frames between them the view could not hold (a view swinging at a U-turn's end wall,
  // discarded as a motion the platform cannot make): no run, however they grow.
  FaultWatch swing(0.3, 0.5);
  CHECK_FALSE(swing.diverging(0.0, 0.2));
  CHECK_FALSE(swing.diverging(kFrameS, 0.52));
  swing.interrupt();
  CHECK_FALSE(swing.diverging(9 * kFrameS, 0.556));
  CHECK_FALSE(swing.diverging(10 * kFrameS, 0.6));
  CHECK(swing.diverging(11 * kFrameS, 1.5));  // three in a row from 0.556: 2.7 times
  // A view that landed beyond the body's reach (a look-alike 0.46 m ahead) and held there: its rising corrections
  // are no stall's; one within reach starts the run.
  FaultWatch lookAlike(0.3, 0.5);
  CHECK_FALSE(lookAlike.diverging(0.0, 0.05, false));
  CHECK_FALSE(lookAlike.diverging(kFrameS, 0.1, false));
  CHECK_FALSE(lookAlike.diverging(2 * kFrameS, 0.18, false));
  CHECK_FALSE(lookAlike.diverging(3 * kFrameS, 0.033, true));
  CHECK_FALSE(lookAlike.diverging(4 * kFrameS, 0.066, false));
  CHECK(lookAlike.diverging(5 * kFrameS, 0.099, false));
}

namespace {
// A correction from the wheels' pose to the view's: the camera centre moved by `offset`, turned by `yawDeg`.
Eigen::Isometry3d correction(const Eigen::Vector3d& offset, double yawDeg) {
  Eigen::Isometry3d c(Eigen::AngleAxisd(yawDeg * kDeg, Eigen::Vector3d::UnitY()));
  c.translation() = offset;
  return c;
}
}  // namespace

TEST_CASE("a view that corrects the wheels by the same offset frame after frame holds the map; one that moves does not",
          "[odometry][faults]") {
  // The way back meets the way out's map, offset by the drift between (a held-out U-turn: 0.04, -0.01, 0.03 m and
  // 2.4-2.6 deg on every frame, the millimetres of ICP's noise between them): after the decision time the view stands.
  FaultWatch back(0.3, 0.5);
  const Eigen::Vector3d offset(0.040, -0.005, 0.028);
  const double jitter[] = {0.0, 0.004, -0.003, 0.006, -0.005, 0.002, 0.004, -0.006, 0.003, 0.0};
  for (int i = 0; i < 9; ++i) {
    const Eigen::Vector3d noise(0.002, jitter[i], -jitter[i] / 2);
    CHECK_FALSE(back.steady(i * kFrameS, correction(offset + noise, 2.4 + 0.02 * i), 0.011, true));
  }
  CHECK(back.steady(0.31, correction(offset, 2.6), 0.011, true));  // 0.3 s of one correction
  CHECK(back.fault() == WheelFault::disputed);

  // A look-alike discarded frame after frame from the wheels' prediction: its correction moves with the robot's
  // steps (0.05 -> 0.18 m over a second), never one offset.
  FaultWatch lookAlike(0.3, 0.5);
  for (int i = 0; i < 30; ++i)
    CHECK_FALSE(lookAlike.steady(i * kFrameS, correction({0.05 + 0.0045 * i, 0.0, 0.0}, 0.0), 0.011, true));
  // A turn that keeps changing (a view swinging at an end wall) is no steady correction either.
  FaultWatch swing(0.3, 0.5);
  for (int i = 0; i < 30; ++i)
    CHECK_FALSE(swing.steady(i * kFrameS, correction({0.02, 0.0, 0.0}, (i % 2 ? 1.0 : -1.0) * 2.0), 0.011, true));
  // Beyond the reach of the wheels' error (a place a door's spacing away), however steady: no run starts.
  FaultWatch far(0.3, 0.5);
  for (int i = 0; i < 30; ++i) CHECK_FALSE(far.steady(i * kFrameS, correction({1.2, 0.0, 0.0}, 0.0), 0.011, false));
  // A run broken by a frame the view could not hold starts again.
  FaultWatch broken(0.3, 0.5);
  for (int i = 0; i < 8; ++i) CHECK_FALSE(broken.steady(i * kFrameS, correction(offset, 2.5), 0.011, true));
  broken.interrupt();
  for (int i = 8; i < 17; ++i) CHECK_FALSE(broken.steady(i * kFrameS, correction(offset, 2.5), 0.011, true));
  CHECK(broken.steady(8 * kFrameS + 0.31, correction(offset, 2.5), 0.011, true));
}

TEST_CASE("the map's agreement: a fraction of the recent median", "[odometry][faults]") {
  MapAgreement agreement(0.5);
  CHECK(agreement.holds(0.0));  // no history: nothing to hold against
  for (int i = 0; i < 90; ++i) agreement.add(0.8 + 0.01 * (i % 3));
  CHECK(agreement.floor() == Approx(0.405).margin(1e-9));
  CHECK(agreement.holds(0.62));  // a driving frame after a standing spell
  CHECK_FALSE(agreement.holds(0.3));  // a view elsewhere
  for (int i = 0; i < 90; ++i) agreement.add(0.6);  // the old frames leave the window
  CHECK(agreement.floor() == Approx(0.3).margin(1e-9));
}

TEST_CASE("a view the map does not contradict: it holds the map, or the model covers less of it than usual",
          "[odometry][faults]") {
  MapAgreement map(0.5);
  for (int i = 0; i < 90; ++i) {
    map.add(0.67);
    map.addCoverage(0.57);
  }
  CHECK(map.uncontradicted(0.6, 0.55));        // it holds the map
  CHECK(map.uncontradicted(0.32, 0.34));       // after a cover: the region ahead mapped only from afar
  CHECK_FALSE(map.covered(0.34));
  CHECK_FALSE(map.uncontradicted(0.25, 0.55));  // a model as whole as usual, and the view elsewhere
  // A model covering less than usual of which the view agrees with none: contradicted all the same (a robot set
  // down mid-turn 8 m back, the model at the wheels' pose covering 0.57-0.72 of the view against 0.97 before).
  CHECK_FALSE(map.covered(0.4));
  CHECK(map.contradicted(0.0, 0.4));
  CHECK(map.contradicted(0.1, 0.4));
  CHECK_FALSE(map.contradicted(0.2, 0.34));  // a part seen only from afar, a fifth of it agreeing: no evidence
  CHECK_FALSE(map.contradicted(0.0, 0.0));   // paired with nothing (a blank view, an empty model): none
}

TEST_CASE("the mount's tilt error from the turns: learnt after enough turning, zero without error",
          "[odometry][mount]") {
  // The true mount turns the camera about its up axis (-y in the optical frame); the assumed one is pitched 2
  // degrees: the wheels' turns appear about an axis 2 degrees off.
  const Eigen::Vector3d up(0, -1, 0);
  const Eigen::Matrix3d E = Eigen::AngleAxisd(2.0 * kDeg, Eigen::Vector3d::UnitX()).toRotationMatrix();
  MountCalibration mount, clean;
  for (int i = 0; i < 60; ++i) {
    const Eigen::Matrix3d view = Eigen::AngleAxisd(3.0 * kDeg, up).toRotationMatrix();  // a U-turn's frame
    OdometryStep raw;
    raw.delta.linear() = E.transpose() * view * E;  // the same turn seen through the assumed mount
    raw.up = E.transpose() * up;
    raw.dt = kFrameS;
    mount.learn(view, raw);
    OdometryStep exact = raw;
    exact.delta.linear() = view;
    exact.up = up;
    clean.learn(view, exact);
    if (i == 25) {  // 78 degrees seen: not yet, and the mount's tilt is as uncertain as configured
      CHECK(mount.errorDeg() == 0.0);
      CHECK(mount.sigmaDeg(2.0) == 2.0);
    }
  }
  CHECK(mount.sigmaDeg(2.0) < 0.5);  // learnt: its tilt now known to a fraction of the configured sigma
  CHECK(clean.sigmaDeg(2.0) < 0.5);  // and known to be right
  CHECK(mount.turnSeenDeg() == Approx(180.0));
  CHECK(mount.errorDeg() == Approx(2.0).margin(0.01));
  CHECK(clean.errorDeg() < 1e-6);
  // Corrected, the wheels' turn is the view's.
  OdometryStep raw;
  raw.delta.linear() = E.transpose() * Eigen::AngleAxisd(3.0 * kDeg, up).toRotationMatrix() * E;
  raw.up = E.transpose() * up;
  const OdometryStep fixed = mount.correct(raw);
  CHECK((fixed.delta.linear() - Eigen::AngleAxisd(3.0 * kDeg, up).toRotationMatrix()).norm() < 1e-6);
  CHECK((fixed.up - up).norm() < 1e-6);
}

namespace {

// An in-place turn: still, the rate ramping up to 60 deg/s over 0.5 s, turning, ramping down, still (seconds).
double yawAt(double t) {
  const double rate = 60.0 * kDeg, ramp = 0.5, start = 1.0, cruise = 2.0;
  auto integral = [&](double u) {  // of the rate from `start`, u seconds in
    if (u <= 0) return 0.0;
    if (u <= ramp) return rate * u * u / (2 * ramp);
    if (u <= ramp + cruise) return rate * ramp / 2 + rate * (u - ramp);
    const double d = std::min(u - ramp - cruise, ramp);
    return rate * ramp / 2 + rate * cruise + rate * d - rate * d * d / (2 * ramp);
  };
  return integral(t - start);
}

Eigen::Isometry3d turned(double yaw) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return p;
}

// The wheels' track of the turn, stamped `latencyS` late; the view's frames (their true stamps) through it.
double learntOffset(double latencyS, double (*yaw)(double), bool* learnt = nullptr, double noiseRad = 0.0) {
  OdometryConfig c;
  c.timeOffsetRangeS = 0.2;  // learning on (off by default)
  OdometryTrack track;
  for (double t = 0.0; t < 6.0; t += 0.01) {
    OdometrySample s;
    s.timestamp = t + latencyS;
    s.T_camera_to_odom = turned(yaw(t));
    track.add(s);
  }
  TimeOffset offset(c);
  unsigned state = 12345;  // the view's noise: uniform, of standard deviation noiseRad, the same every run
  auto noise = [&] {
    state = state * 1103515245u + 12345u;
    return noiseRad * std::sqrt(12.0) * (static_cast<double>((state >> 8) & 0xffff) / 65535.0 - 0.5);
  };
  for (int i = 1; i * kFrameS < 5.0; ++i) {
    const double t0 = (i - 1) * kFrameS, t1 = i * kFrameS;
    offset.add(track, t0, t1, Eigen::Vector3d(noise(), noise(), yaw(t1) - yaw(t0) + noise()));
  }
  if (learnt) *learnt = offset.learnt();
  return offset.offset();
}

}  // namespace

TEST_CASE("the odometry's latency is learnt from the changes of turn rate, within its range",
          "[odometry][faults]") {
  bool learnt = false;
  CHECK(learntOffset(0.04, yawAt, &learnt) == Approx(0.04).margin(0.006));
  CHECK(learnt);
  CHECK(learntOffset(-0.07, yawAt) == Approx(-0.07).margin(0.006));
  CHECK(learntOffset(0.0, yawAt) == Approx(0.0).margin(0.006));
  // Beyond the range (0.2 s) it stops at its edge rather than wandering.
  CHECK(learntOffset(0.35, yawAt) <= 0.2 + 1e-9);
  // A constant turn rate (or none) matches every offset alike: no evidence, the start value stays.
  CHECK(learntOffset(0.04, [](double t) { return 0.5 * t; }, &learnt) == 0.0);
  CHECK_FALSE(learnt);
  CHECK(learntOffset(0.04, [](double) { return 0.0; }, &learnt) == 0.0);
  CHECK_FALSE(learnt);
  // With a view's noise (1 mrad a frame): the same, and noise alone does not move it.
  CHECK(learntOffset(0.04, yawAt, &learnt, 0.001) == Approx(0.04).margin(0.011));
  CHECK(learnt);
  CHECK(std::abs(learntOffset(0.0, yawAt, &learnt, 0.001)) <= 0.011);
  CHECK(learntOffset(0.04, [](double t) { return 0.5 * t; }, &learnt, 0.001) == 0.0);
  CHECK_FALSE(learnt);
}

TEST_CASE("a dispute nothing can decide is dropped; one with fresh evidence is not", "[odometry][faults]") {
  FaultWatch watch(0.3, 0.5);
  CHECK(watch.diverging(0.0, 0.05) == false);  // one frame's inertia opens it, undecided
  CHECK(watch.fault() == WheelFault::disputed);
  watch.expire(0.5);
  CHECK(watch.fault() == WheelFault::disputed);  // within three decision times
  watch.expire(0.95);
  CHECK(watch.fault() == WheelFault::none);
  // Fresh evidence keeps it open (too little yet to decide it): three decision times from its last frame.
  watch.viewContradicted(2.0);
  watch.viewContradicted(2.8);
  watch.expire(3.5);
  CHECK(watch.fault() == WheelFault::disputed);
  watch.expire(3.8);
  CHECK(watch.fault() == WheelFault::none);
}

TEST_CASE("after a covered lens, a view back in front of an empty model is fused at the wheels' pose",
          "[odometry][faults]") {
  // The moving volume followed the wheels' pose while the lens was covered and shifted into space nothing mapped:
  // the view, back, pairs with nothing (inliers 0). It was taken for a blank frame and never fused, so the model
  // stayed empty and the run was lost when the dead-reckoning budget ran out. A blank frame is not fused.
  OdometryConfig c;
  auto track = std::make_shared<OdometryTrack>();
  for (int i = 0; i <= 300; ++i) {  // 3 s at 1 m/s along the camera's z
    OdometrySample s;
    s.timestamp = i * 0.01;
    s.T_camera_to_odom.translation() = Eigen::Vector3d(0, 0, s.timestamp);
    track->add(s);
  }
  MotionModel model(c);
  model.setTrack(track);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  double stamp = 0.0;
  auto frame = [&](bool blank, double inliers) {
    FrameOdometry out;
    const double next = stamp + kFrameS;
    const FrameMotion motion = model.predict(pose, stamp, true, next, out);
    sb::FrameResult r;
    r.timestamp = next;
    r.trackingAttempted = true;  // tracked and failed: no pair agreed
    r.inlierFraction = inliers;
    sb::Decision d;
    std::string implausible;
    const FrameView view{r, d, out, implausible, nullptr};
    model.depthSeen(blank);
    REQUIRE(model.follow(view, motion));
    pose = *d.correctedPose;
    stamp = next;
    model.finished(pose, stamp, false, out);
    return std::make_pair(out.fused, d.integrate.value_or(true));  // unset: the controller's word, to integrate
  };
  for (int i = 0; i < 10; ++i) CHECK(frame(true, 0.0) == std::make_pair(false, false));  // covered
  CHECK(frame(false, 0.0) == std::make_pair(true, true));  // back, the model in view empty: fused
}

TEST_CASE("a turn error under one frame's gate but the same on every frame is a fault; noise and a learnt drift are not",
          "[odometry][faults]") {
  // The defaults' gate: 5 sigmas of a step, at least 0.03 rad (1.7 degrees) a frame.
  constexpr double kSigmas = 5.0, kFloor = 0.03, kSigmaRad = 0.0005;
  const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  auto framesUntilFault = [&](const std::function<Eigen::Vector3d(int)>& turnAt, int frames) {
    TurnCorrections window;
    for (int i = 0; i < frames; ++i)
      if (!window.add(i * kFrameS, turnAt(i), kSigmaRad, kSigmas, kFloor).empty()) return i;
    return -1;
  };
  // A gyro biased by 20 deg/s: 0.67 degrees a frame, each under the 1.7 degree gate; found within the window.
  const int gyro = framesUntilFault([&](int) { return up * (20.0 * kFrameS * kDeg); }, 300);
  CHECK(gyro >= 2);
  CHECK(gyro <= 10);
  // What wheels get wrong legitimately: a drift the calibration has not learnt yet (0.3 deg/s), a turn scale 5% off
  // at 90 deg/s, and a view's noise of 1 degree a frame either way: never.
  CHECK(framesUntilFault([&](int) { return up * (0.3 * kFrameS * kDeg); }, 300) == -1);
  CHECK(framesUntilFault([&](int) { return up * (0.05 * 90.0 * kFrameS * kDeg); }, 300) == -1);
  CHECK(framesUntilFault([&](int i) { return up * ((i % 2 ? 1.0 : -1.0) * kDeg); }, 300) == -1);
  // Still wrong: every frame is evidence. Right again: the fault's frames still in the window are not.
  TurnCorrections window;
  for (int i = 0; i < 30; ++i) {
    const bool fault = !window.add(i * kFrameS, up * (20.0 * kFrameS * kDeg), kSigmaRad, kSigmas, kFloor).empty();
    if (i >= 10) CHECK(fault);
  }
  for (int i = 30; i < 90; ++i) CHECK(window.add(i * kFrameS, Eigen::Vector3d::Zero(), kSigmaRad, kSigmas, kFloor).empty());
}
