#pragma once
// The wheel odometry of a synthetic drive (stress_drive.h), as a cheap wheeled base would report it, written
// as the sequence's odometry.txt (odometry/odometry_track.h reads it).
//
// The odometry frame is the base's odometry frame after ROS REP 103 (x forward, y left, z up), equal to the
// base frame at the drive's start; each sample is T_camera_to_odom: the base's odometry pose composed with
// the camera mount (DrivePath::cameraToBase: the optical frame, x right, y down, z forward, 1.2 m up), the
// convention of groundtruth.txt's camera. Stamps are on depth.txt's clock, at the odometry's own rate, offset
// from the frames by a seeded fraction of a period (so the first frame, at 0 s, precedes the first sample).
//
// Errors are applied to each increment of the base's planar motion (dx, dy in the base frame, dyaw) and
// integrated, as wheel odometry does, so the drift grows with the distance driven and the time:
//   dx' = (1 + scale) dx + n sqrt(|d|),  dyaw' = (1 + yawScale) dyaw + yawBias dt + m sqrt(dt)
// with n, m normal draws (seeded), and an optional wheel slip: one step reads slipM more forward motion.

#include <cstdint>
#include <string>

#include "core/trajectory.h"
#include "synth/drive_faults.h"
#include "synth/stress_drive.h"

namespace sb::synth {

// Defaults: a cheap base (issue 41: 3% scale, 2% yaw scale, 0.3 deg/s yaw bias).
struct OdometryErrors {
  double rateHz = 50.0;               // samples per second
  double scale = 0.03;                // distance driven reads this fraction more (negative: less)
  double yawScale = 0.02;             // turns read this fraction more
  double yawBiasDegps = 0.3;          // yaw drift, degrees per second (gyro-like; also at rest)
  double noiseMPerSqrtM = 0.002;      // translation noise: std of the random walk after 1 m, metres
  double yawNoiseDegPerSqrtS = 0.02;  // yaw noise: std of the random walk after 1 s, degrees
  double slipAtS = -1.0;              // a wheel slip at this time, seconds (negative: none)
  double slipM = 0.4;                 // the slip's extra forward reading in that one step, metres

  // Throws sb::Error naming the first value out of range (a rate of 1-1000 Hz, scales within +-50%, ...).
  void validate() const;
  // One line stating every value, for odometry.txt's header and README lines.
  std::string describe() const;
};

// The drive's odometry from `startS` (0: the drive's start) up to `endS` seconds (at least one sample at or
// after it). The odometry frame is the base at `startS` (a robot started there). `seed` and `startS` seed the
// noise and the stamps' offset: a part started later draws noise of its own. `faults` (drive_faults.h): the
// truth's stall or carry as the wheels read it (a stall's spin, a carry's stillness), the stamps' latency, the
// mount the odometry assumes and the wrong wheels within their window.
Trajectory driveOdometry(const stress::DrivePath& path, double endS, const OdometryErrors& errors,
                         uint64_t seed, double startS = 0.0, const DriveFaults& faults = {});

// Writes `odometry` as a TUM-format odometry.txt whose header comment states the convention and `errors`.
// Throws sb::Error naming the file.
void writeOdometryFile(const std::string& path, const Trajectory& odometry, const OdometryErrors& errors,
                       uint64_t seed, const DriveFaults& faults = {});

}  // namespace sb::synth
