#pragma once
// What the stress trajectories (stress_trajectory.h) are made of: camera key states, minimum-jerk moves
// between them, and the sampler that plays the moves at the frame rate and adds the sway. Shared by the
// stress kinds' files; not part of the synth API.

#include <Eigen/Geometry>
#include <vector>

#include "synth/rng.h"
#include "synth/stress_trajectory.h"

namespace sb::synth::stress {

constexpr double kPi = 3.141592653589793;
constexpr double kTwoPi = 2.0 * kPi;
constexpr double kMinJerkPeak = 1.875;  // peak of d/dtau of the minimum-jerk profile 10t^3 - 15t^4 + 6t^5
constexpr double kEyeHeightM = 1.35;    // camera height above the floor, metres (as the ICL-NUIM cameras)
constexpr double kLevelPitchRad = 0.2;  // usual downward tilt of a handheld camera
constexpr double kDegToRad = kPi / 180.0;

struct CameraState {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // metres, world
  double yawRad = 0.0;                                 // forward (sin yaw, 0, cos yaw) before pitch
  double pitchDownRad = kLevelPitchRad;
};

// A minimum-jerk move from the previous state to `target` over `durationS` seconds.
struct Move {
  const char* label;
  double durationS;
  CameraState target;
};

// Amplitudes of the sway added to every frame: position x, y, z (metres) and yaw, pitch, roll (radians).
struct Sway {
  double positionM[3];
  double angleRad[3];
};

// The hand sway of StressParams (the same amplitude on every axis).
Sway handSway(const StressParams& p);

// 10t^3 - 15t^4 + 6t^5: 0 at 0, 1 at 1, zero speed and acceleration at both ends.
double minJerk(double tau);

// Samples the moves at `fps` (frame i at t = i / fps, the last frame at the end of the last move), adds the
// sway (seeded phases, incommensurate frequencies) and labels the frames with their moves' labels.
StressTrajectory play(const CameraState& start, const std::vector<Move>& moves, double fps, const Sway& sway,
                      Rng& rng);
inline StressTrajectory play(const CameraState& start, const std::vector<Move>& moves, const StressParams& p,
                             Rng& rng) {
  return play(start, moves, p.fps, handSway(p), rng);
}

// Camera right (image +x) in the horizontal plane for a camera facing `yaw`.
Eigen::Vector3d lateralOf(double yaw);
// Camera forward in the horizontal plane for a camera facing `yaw`.
Eigen::Vector3d forwardOf(double yaw);
// The camera-to-world pose of a state (no roll, no sway).
Eigen::Isometry3d poseOf(const CameraState& s);
// Yaw of a camera looking along the plan direction `d` (x, z).
double yawOf(const Eigen::Vector2d& d);
// The camera height of the scenes' handheld cameras: kEyeHeightM above the floor (world y; floor at +y).
double eyeY(const Scene& scene);

}  // namespace sb::synth::stress
