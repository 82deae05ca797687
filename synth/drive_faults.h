#pragma once
// Faults of a synthetic drive's base (issue 52), for the tests of what the runtime does when the wheels and the
// view disagree. Two kinds:
//   - the truth departs from the wheels: a stall (the robot stands, e.g. against an obstacle, while its wheels
//     spin on) and a carry (the robot is picked up and set down further back on its path; the wheels never
//     turn). They change the camera's true path: DriveClock maps a frame's time to the drive's.
//   - the odometry's own errors of geometry and time: its stamps late by a latency, and the camera mount it
//     assumes off from the true one.
//   - grossly wrong wheels for a window of time (issue 52's attack): the odometry's steps reversed, reading zero,
//     turned by a gyro bias or scaled, while the truth drives on unchanged.
// Each is off by default; describe() states those that are on, for odometry.txt's header.

#include <array>
#include <string>

#include "synth/stress_drive.h"

namespace sb::synth {

// How the wheels are wrong within DriveFaults' window. A step is one sample's planar increment (forward, left, turn)
// as the wheels read it, their errors and noise included.
enum class WrongWheels {
  None,
  Reversed,  // each step read backwards: the forward, left and turn increments negated (both encoders' signs)
  Zero,      // the odometry reads no motion at all (no step, no turn, no drift) while the robot drives
  Gyro,      // the turn drifts by a further `wrongValue` deg/s (a gyro's bias)
  Scaled,    // each step, its turn too, times `wrongValue`
};

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
  WrongWheels wrong = WrongWheels::None;  // wrong wheels in the samples whose true time is in (wrongAtS, ...
  double wrongAtS = -1.0;                 // ... wrongAtS + wrongS], seconds (the truth is unchanged)
  double wrongS = 10.0;
  double wrongValue = 0.0;  // Gyro: the bias, deg/s; Scaled: the factor; unused otherwise


  bool changesTruth() const { return stallAtS >= 0.0 || carriedAtS >= 0.0; }
  // Throws sb::Error naming the first value out of range.
  void validate() const;
  // The faults that are on, one phrase each ("" when none).
  std::string describe() const;
  // Whether the sample at true time `t` is within the wrong wheels' window.
  bool wrongAt(double t) const;
  // One sample's step as the wheels read it (forward dx, left dy, turn dyaw, radians; over dt seconds), made
  // wrong when `t` is within the window.
  void applyWrongWheels(double t, double dt, double& dx, double& dy, double& dyaw) const;
};

// The names --odom-wrong takes ("reversed", "zero", "gyro", "scaled"), and the kind a name is (throws sb::Error
// naming the value and the choices).
std::string wrongWheelsName(WrongWheels kind);
WrongWheels parseWrongWheels(const std::string& name);
// `text` as KIND,AT,SECONDS[,VALUE] (--odom-wrong) into `faults`: VALUE is gyro's bias in deg/s (default 20) and
// scaled's factor (default 2); reversed and zero take none. Throws sb::Error naming the option and the value.
void parseWrongWheelsOption(const std::string& text, DriveFaults& faults);

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
