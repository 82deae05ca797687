#pragma once
// Faults of a synthetic drive's base (issue 52), for the tests of what the runtime does when the wheels and the
// view disagree. Two kinds:
//   - the truth departs from the wheels: a stall (the robot stands, e.g. against an obstacle, while its wheels
//     spin on) and a carry (the robot is picked up and set down further back on its path; the wheels never
//     turn). They change the camera's true path: DriveClock maps a frame's time to the drive's.
//   - the odometry's own errors of geometry and time: its stamps late by a latency, and the camera mount it
//     assumes off from the true one.
// Each is off by default; describe() states those that are on, for odometry.txt's header.

#include <array>
#include <string>

#include "synth/stress_drive.h"

namespace sb::synth {

struct DriveFaults {
  double stallAtS = -1.0;      // the robot stands from this time, seconds (negative: no stall) ...
  double stallS = 3.0;         // ... for this long ...
  double stallSpeedMps = 1.0;  // ... while its wheels read this forward speed
  double carriedAtS = -1.0;    // the robot is lifted at this time, seconds (negative: not carried) ...
  double carriedBackM = 11.0;  // ... and set down this far back along its path (the wheels never turn)
  double latencyS = 0.0;       // the odometry's stamps are this much later than its poses' true time
  // The mount the odometry assumes: the true one turned by roll, pitch, yaw (degrees, about the camera's optical
  // axes z, x, y) and moved by x, y, z (metres, in the camera's frame).
  std::array<double, 6> mountError{};

  bool changesTruth() const { return stallAtS >= 0.0 || carriedAtS >= 0.0; }
  // Throws sb::Error naming the first value out of range.
  void validate() const;
  // The faults that are on, one phrase each ("" when none).
  std::string describe() const;
};

// The drive's time at a frame's (or a sample's true) time `t`: held through a stall, jumped back at a carry.
class DriveClock {
 public:
  DriveClock(const stress::DrivePath& path, const DriveFaults& faults);
  double at(double t) const;
  // The robot stands at `t` while its wheels spin (within the stall).
  bool stalled(double t) const;
  // The robot was carried between `t0` and `t1` (its wheels saw none of that motion).
  bool carriedBetween(double t0, double t1) const;

 private:
  DriveFaults faults_;
  double backS_ = 0.0;  // how far back in the drive's time the carry sets the robot down
};

// The camera mount the odometry assumes (`trueMount` turned and moved by faults.mountError).
Eigen::Isometry3d assumedMount(const Eigen::Isometry3d& trueMount, const DriveFaults& faults);

}  // namespace sb::synth
