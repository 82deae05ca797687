#pragma once
// The drive stress (stress_trajectory.h describes it): a wheeled robot driving a corridor's length and back,
// in the corridor scene (corridor_scene.h).

#include <Eigen/Geometry>
#include <cstdint>
#include <string>

#include "synth/rng.h"
#include "synth/scene.h"
#include "synth/stress_trajectory.h"

namespace sb::synth::stress {

// The drive as a function of time: the base's path on the floor and the camera on it. The camera frames
// (driveTrajectory) and the wheel odometry (drive_odometry.h) are both sampled from it.
class DrivePath {
 public:
  // Draws the seeded choices (cruise speed, pitch, vibration phases) from `rng`. `scene` must be
  // generateCorridor's; throws sb::Error otherwise, or when the corridor is too short to reach the cruise
  // speed.
  DrivePath(const Scene& scene, const StressParams& p, Rng& rng);

  double durationS() const { return 2.0 * legS_ + turnS_; }
  // The camera's pose in the world at `t` seconds (clamped to the drive), chassis vibration included.
  Eigen::Isometry3d cameraToWorld(double t) const;
  // The base at `t` (clamped): its frame after ROS REP 103 (x forward, y left, z up), on the floor under the
  // camera, in the scene's world frame (x, y down, z: the frames' world).
  Eigen::Isometry3d baseToWorld(double t) const;
  // The camera mount: the camera's optical frame in the base frame, without vibration (camera height up,
  // pitched down by the drive's seeded pitch, looking along the base's x).
  Eigen::Isometry3d cameraToBase() const;
  // The segment label at `t`: accelerate, drive, brake, turn.
  std::string label(double t) const;

 private:
  struct Plan {
    Eigen::Vector2d q, heading;  // plan (x, z): position and unit heading
    std::string label;
  };
  Plan plan(double t) const;

  double r_, z0_, zTurn_, speed_, rampS_, distanceM_, legS_, turnS_, cameraY_, floorY_, pitch_;
  double turnRateRad_;
  double phase_[3];
};

// `scene` must be generateCorridor's. Throws sb::Error otherwise, or when the corridor is too short to reach
// the cruise speed.
StressTrajectory driveTrajectory(const Scene& scene, const StressParams& p, Rng& rng);

}  // namespace sb::synth::stress

namespace sb::synth {

// The path of `stressTrajectory(StressKind::Drive, scene, seed, params)`: the same seeded drive, for the
// odometry of its sequence (drive_odometry.h). Throws as DrivePath does.
stress::DrivePath drivePath(const Scene& scene, uint64_t seed, const StressParams& params = {});

}  // namespace sb::synth
