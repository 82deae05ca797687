#include "synth/stress_moves.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "synth/builtin_trajectory.h"

namespace sb::synth::stress {

namespace {

// Hand-sway frequencies (Hz), incommensurate: x, y, z, yaw, pitch, roll.
constexpr double kSwayHz[6] = {0.37, 0.27, 0.21, 0.16, 0.23, 0.33};

CameraState lerp(const CameraState& a, const CameraState& b, double s) {
  return {a.position + s * (b.position - a.position), a.yawRad + s * (b.yawRad - a.yawRad),
          a.pitchDownRad + s * (b.pitchDownRad - a.pitchDownRad)};
}

}  // namespace

Sway handSway(const StressParams& p) {
  return {{p.swayPositionM, p.swayPositionM, p.swayPositionM},
          {p.swayAngleRad, p.swayAngleRad, p.swayAngleRad}};
}

double minJerk(double tau) {
  return tau * tau * tau * (10.0 + tau * (-15.0 + 6.0 * tau));
}

StressTrajectory play(const CameraState& start, const std::vector<Move>& moves, double fps, const Sway& sway,
                      Rng& rng) {
  double total = 0.0;
  for (const Move& m : moves) total += m.durationS;
  const size_t frames = static_cast<size_t>(std::floor(total * fps + 1e-9)) + 1;
  double phase[6];
  for (double& ph : phase) ph = rng.uniform(0.f, static_cast<float>(kTwoPi));
  auto wave = [&](int axis, double t) { return std::sin(kTwoPi * kSwayHz[axis] * t + phase[axis]); };

  StressTrajectory out;
  out.poses.reserve(frames);
  CameraState from = start;
  size_t move = 0;
  double moveStart = 0.0;
  for (size_t i = 0; i < frames; ++i) {
    const double t = static_cast<double>(i) / fps;
    while (move + 1 < moves.size() && t >= moveStart + moves[move].durationS) {
      from = moves[move].target;
      moveStart += moves[move].durationS;
      ++move;
    }
    const double tau = std::clamp((t - moveStart) / moves[move].durationS, 0.0, 1.0);
    const CameraState s = lerp(from, moves[move].target, minJerk(tau));
    TimedPose pose;
    pose.timestamp = t;
    pose.T_camera_to_world.linear() =
        handheldRotation(s.yawRad + sway.angleRad[0] * wave(3, t),
                         s.pitchDownRad + sway.angleRad[1] * wave(4, t), sway.angleRad[2] * wave(5, t));
    pose.T_camera_to_world.translation() =
        s.position + Eigen::Vector3d(sway.positionM[0] * wave(0, t), sway.positionM[1] * wave(1, t),
                                     sway.positionM[2] * wave(2, t));
    out.poses.push_back(pose);
    const std::string label = moves[move].label;
    if (out.segments.empty() || out.segments.back().label != label) out.segments.push_back({label, i, i});
    out.segments.back().end = i + 1;
  }
  return out;
}

Eigen::Vector3d lateralOf(double yaw) {
  return {std::cos(yaw), 0.0, -std::sin(yaw)};
}

Eigen::Vector3d forwardOf(double yaw) {
  return {std::sin(yaw), 0.0, std::cos(yaw)};
}

Eigen::Isometry3d poseOf(const CameraState& s) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = handheldRotation(s.yawRad, s.pitchDownRad, 0.0);
  T.translation() = s.position;
  return T;
}

double yawOf(const Eigen::Vector2d& d) {
  return std::atan2(d.x(), d.y());
}

double eyeY(const Scene& scene) {
  return scene.roomMax.y() - kEyeHeightM;
}

}  // namespace sb::synth::stress
