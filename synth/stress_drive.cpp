#include "synth/stress_drive.h"

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

StressTrajectory driveTrajectory(const Scene& scene, const StressParams& p, Rng& rng) {
  if (scene.name != kCorridorSceneName)
    throw Error("synth: --stress drive runs in the corridor scene (--scene corridor), not '" + scene.name +
                "'");
  const double length = scene.roomMax.z() - scene.roomMin.z();
  const double z0 = scene.roomMin.z() + p.driveEndMarginM, zTurn = scene.roomMax.z() - p.driveEndMarginM;
  const double speed =
      rng.uniform(static_cast<float>(p.driveMinSpeedMps), static_cast<float>(p.driveMaxSpeedMps));
  const Leg leg{zTurn - z0, speed, p.driveAccelerateS};
  if (leg.cruiseS() <= 0.0)
    throw Error("synth: a " + std::to_string(length) +
                " m corridor is too short for --stress drive to reach " + std::to_string(speed) +
                " m/s; use a corridor of at least " +
                std::to_string(2.0 * p.driveEndMarginM + speed * p.driveAccelerateS + 0.5) + " m");
  const double pitch = rng.uniform(0.f, static_cast<float>(p.driveMaxPitchDownRad));
  double phase[3];
  for (double& ph : phase) ph = rng.uniform(0.f, static_cast<float>(kTwoPi));
  auto vibration = [&](int axis, double t) {
    return std::sin(kTwoPi * kVibrationHz[axis] * t + phase[axis]);
  };

  const double r = p.driveLaneM;
  const double turnS = kMinJerkPeak * kPi / (p.driveTurnRateDegps * kDegToRad);
  const double legS = leg.durationS(), totalS = 2.0 * legS + turnS;
  const double cameraY = scene.roomMax.y() - p.driveCameraHeightM;
  const size_t frames = static_cast<size_t>(std::floor(totalS * p.fps + 1e-9)) + 1;
  StressTrajectory out;
  out.poses.reserve(frames);
  for (size_t i = 0; i < frames; ++i) {
    const double t = static_cast<double>(i) / p.fps;
    Eigen::Vector2d q, heading;  // plan (x, z)
    std::string label;
    if (t < legS) {  // out along the +x lane
      q = {r, z0 + leg.at(t)};
      heading = {0.0, 1.0};
      label = leg.label(t);
    } else if (t < legS + turnS) {  // U-turn about (0, zTurn), counter-clockwise in the plan
      const double phi = kPi * minJerk((t - legS) / turnS);
      q = {r * std::cos(phi), zTurn + r * std::sin(phi)};
      heading = {-std::sin(phi), std::cos(phi)};
      label = "turn";
    } else {  // back along the -x lane
      const double u = t - legS - turnS;
      q = {-r, zTurn - leg.at(u)};
      heading = {0.0, -1.0};
      label = leg.label(u);
    }
    TimedPose pose;
    pose.timestamp = t;
    pose.T_camera_to_world.linear() = handheldRotation(
        yawOf(heading), pitch + kVibrationRad * vibration(1, t), kVibrationRad * vibration(2, t));
    pose.T_camera_to_world.translation() =
        Eigen::Vector3d(q.x(), cameraY + kVibrationM * vibration(0, t), q.y());
    out.poses.push_back(pose);
    if (out.segments.empty() || out.segments.back().label != label) out.segments.push_back({label, i, i});
    out.segments.back().end = i + 1;
  }
  return out;
}

}  // namespace sb::synth::stress
