#include "synth/builtin_trajectory.h"

#include <Eigen/Geometry>
#include <cmath>

namespace sb::synth {

namespace {
constexpr double kTwoPi = 6.283185307179586;
// Sway frequencies (Hz): incommensurate so the motion does not visibly repeat.
constexpr double kSwayHzX = 0.31, kSwayHzY = 0.23, kSwayHzZ = 0.17;
constexpr double kSwayHzYaw = 0.13, kSwayHzPitch = 0.19, kSwayHzRoll = 0.29;
}  // namespace

Eigen::Matrix3d handheldRotation(double yaw, double pitchDown, double roll) {
  // Pitching down turns forward towards +y (the floor).
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(-pitchDown, Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

Trajectory builtinTrajectory(size_t frames, const BuiltinTrajectoryParams& p) {
  Trajectory out;
  out.reserve(frames);
  for (size_t i = 0; i < frames; ++i) {
    const double t = static_cast<double>(i) / p.fps;
    const double angle = p.startAngleRad + kTwoPi * t / p.orbitPeriodS;
    auto sway = [t](double hz) { return std::sin(kTwoPi * hz * t); };
    const Eigen::Vector3d position(p.centerX + p.orbitRadiusM * std::sin(angle) + p.swayPositionM * sway(kSwayHzX),
                                   p.centerY + p.swayPositionM * sway(kSwayHzY),
                                   p.centerZ + p.orbitRadiusM * std::cos(angle) + p.swayPositionM * sway(kSwayHzZ));
    const double yaw = angle + p.swayAngleRad * sway(kSwayHzYaw);
    const double pitch = p.pitchDownRad + p.swayAngleRad * sway(kSwayHzPitch);
    const double roll = p.swayAngleRad * sway(kSwayHzRoll);
    TimedPose pose;
    pose.timestamp = t;
    pose.T_camera_to_world.linear() = handheldRotation(yaw, pitch, roll);
    pose.T_camera_to_world.translation() = position;
    out.push_back(pose);
  }
  return out;
}

}  // namespace sb::synth
