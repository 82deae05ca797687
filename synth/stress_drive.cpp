#include "synth/stress_drive.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "synth/builtin_trajectory.h"
#include "synth/corridor_scene.h"
#include "synth/stress_moves.h"

namespace sb::synth::stress {

namespace {

// Vibration of the chassis on the floor (as robot's): amplitude and frequency of height, pitch and roll.
constexpr double kVibrationM = 0.001, kVibrationRad = 0.002;
constexpr double kVibrationHz[3] = {2.9, 2.3, 3.7};

// The integral of minJerk from 0 to tau: 2.5 tau^4 - 3 tau^5 + tau^6 (0.5 at 1).
double minJerkIntegral(double tau) {
  return tau * tau * tau * tau * (2.5 + tau * (-3.0 + tau));
}

// A straight leg of `distanceM` from rest to rest: minimum-jerk speed ramps of `rampS` to and from
// `speedMps`.
struct Leg {
  double distanceM, speedMps, rampS;
  double cruiseS() const { return distanceM / speedMps - rampS; }
  double durationS() const { return 2.0 * rampS + cruiseS(); }
  // Distance travelled at time t (clamped to the leg), metres.
  double at(double t) const {
    const double v = speedMps, Ta = rampS, Tc = cruiseS();
    if (t <= 0.0) return 0.0;
    if (t < Ta) return v * Ta * minJerkIntegral(t / Ta);
    if (t < Ta + Tc) return 0.5 * v * Ta + v * (t - Ta);
    const double u = std::min(t - Ta - Tc, Ta);
    return 0.5 * v * Ta + v * Tc + v * (u - Ta * minJerkIntegral(u / Ta));
  }
  const char* label(double t) const {
    return t < rampS ? "accelerate" : t < rampS + cruiseS() ? "drive" : "brake";
  }
};

}  // namespace

DrivePath::DrivePath(const Scene& scene, const StressParams& p, Rng& rng) {
  if (scene.name != kCorridorSceneName)
    throw Error("synth: --stress drive runs in the corridor scene (--scene corridor), not '" + scene.name +
                "'");
  const double length = scene.roomMax.z() - scene.roomMin.z();
  z0_ = scene.roomMin.z() + p.driveEndMarginM;
  zTurn_ = scene.roomMax.z() - p.driveEndMarginM;
  speed_ = rng.uniform(static_cast<float>(p.driveMinSpeedMps), static_cast<float>(p.driveMaxSpeedMps));
  rampS_ = p.driveAccelerateS;
  distanceM_ = zTurn_ - z0_;
  const Leg leg{distanceM_, speed_, rampS_};
  if (leg.cruiseS() <= 0.0)
    throw Error("synth: a " + std::to_string(length) +
                " m corridor is too short for --stress drive to reach " + std::to_string(speed_) +
                " m/s; use a corridor of at least " +
                std::to_string(2.0 * p.driveEndMarginM + speed_ * p.driveAccelerateS + 0.5) + " m");
  pitch_ = rng.uniform(0.f, static_cast<float>(p.driveMaxPitchDownRad));
  for (double& ph : phase_) ph = rng.uniform(0.f, static_cast<float>(kTwoPi));
  r_ = p.driveLaneM;
  turnRateRad_ = p.driveTurnRateDegps * kDegToRad;
  turnS_ = kMinJerkPeak * kPi / turnRateRad_;
  legS_ = leg.durationS();
  floorY_ = scene.roomMax.y();
  cameraY_ = floorY_ - p.driveCameraHeightM;
}

DrivePath::Plan DrivePath::plan(double t) const {
  const Leg leg{distanceM_, speed_, rampS_};
  t = std::clamp(t, 0.0, durationS());
  if (t < legS_) return {{r_, z0_ + leg.at(t)}, {0.0, 1.0}, leg.label(t)};  // out along the +x lane
  if (t < legS_ + turnS_) {  // U-turn about (0, zTurn), counter-clockwise in the plan
    const double phi = kPi * minJerk((t - legS_) / turnS_);
    return {{r_ * std::cos(phi), zTurn_ + r_ * std::sin(phi)}, {-std::sin(phi), std::cos(phi)}, "turn"};
  }
  const double u = t - legS_ - turnS_;  // back along the -x lane
  return {{-r_, zTurn_ - leg.at(u)}, {0.0, -1.0}, leg.label(u)};
}

std::string DrivePath::label(double t) const { return plan(t).label; }

Eigen::Isometry3d DrivePath::cameraToWorld(double t) const {
  const Plan p = plan(t);
  auto vibration = [&](int axis) { return std::sin(kTwoPi * kVibrationHz[axis] * t + phase_[axis]); };
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = handheldRotation(yawOf(p.heading), pitch_ + kVibrationRad * vibration(1),
                                kVibrationRad * vibration(2));
  T.translation() = Eigen::Vector3d(p.q.x(), cameraY_ + kVibrationM * vibration(0), p.q.y());
  return T;
}

Eigen::Isometry3d DrivePath::baseToWorld(double t) const {
  const Plan p = plan(t);
  // REP 103 axes in the world (y down): x along the heading, z up (-y), y = z x x (left).
  const Eigen::Vector3d x(p.heading.x(), 0.0, p.heading.y()), z(0.0, -1.0, 0.0);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = x;
  T.linear().col(1) = z.cross(x);
  T.linear().col(2) = z;
  T.translation() = Eigen::Vector3d(p.q.x(), floorY_, p.q.y());
  return T;
}

Eigen::Isometry3d DrivePath::cameraToBase() const {
  Eigen::Isometry3d camera = Eigen::Isometry3d::Identity();  // at t = 0 without vibration
  const Plan p = plan(0.0);
  camera.linear() = handheldRotation(yawOf(p.heading), pitch_, 0.0);
  camera.translation() = Eigen::Vector3d(p.q.x(), cameraY_, p.q.y());
  return baseToWorld(0.0).inverse() * camera;
}

StressTrajectory driveTrajectory(const Scene& scene, const StressParams& p, Rng& rng) {
  const DrivePath path(scene, p, rng);
  const size_t frames = static_cast<size_t>(std::floor(path.durationS() * p.fps + 1e-9)) + 1;
  StressTrajectory out;
  out.poses.reserve(frames);
  for (size_t i = 0; i < frames; ++i) {
    const double t = static_cast<double>(i) / p.fps;
    TimedPose pose;
    pose.timestamp = t;
    pose.T_camera_to_world = path.cameraToWorld(t);
    out.poses.push_back(pose);
    const std::string label = path.label(t);
    if (out.segments.empty() || out.segments.back().label != label) out.segments.push_back({label, i, i});
    out.segments.back().end = i + 1;
  }
  return out;
}

}  // namespace sb::synth::stress
