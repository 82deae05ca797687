#pragma once
// What the runtime knows of the platform and of its odometry (docs/odometry.md): the `odometry` section of the
// pipeline config (config/pipeline.json, keys in config/README.md). Every number is physics or a stated noise,
// not a property of one test sequence.

#include <nlohmann/json.hpp>
#include <string>

namespace sb {
class ConfigReader;
}

namespace sb::odometry {

struct OdometryConfig {
  // The platform's limits: no camera on it moves faster, turns faster or accelerates harder than this, so a
  // tracked motion beyond them is not `good` (with or without odometry). A wheeled base stays under about
  // 2 m/s and 0.5 g, a hand-held camera under about 2 m/s and 2-3 g; the defaults leave room for both, and the
  // acceleration's for the estimate's own error: a frame that sticks and the next that catches up on a robot at
  // 1 m/s reads as 60 m/s^2, and the velocity of a stationary camera's tracking jitter as a few m/s^2.
  double maxSpeedMPerS = 3.0;             // m/s
  double maxAccelerationMPerS2 = 100.0;   // m/s^2 (about 10 g), between the velocities of two consecutive frames
  double maxTurnRateDegPerS = 400.0;      // deg/s
  // An estimate may jump where the camera cannot: a pose that stuck for some frames catches up at once when the
  // view fixes it again. Such a jump stands when the view agrees with the model at least as well as on the
  // recent tracked frames (pair agreement at least their median less this margin) and it lies within ICP's
  // reach (beyond the platform's motion by at most maxCorrectionM); a runaway loses agreement (the inliers fall),
  // a frame from elsewhere lies metres away.
  double jumpAgreementMargin = 0.05;      // fraction of the model's pairs
  double maxCorrectionM = 0.5;            // metres
  // The odometry's noise when its samples state no covariance: sigma of the translation of one frame's step,
  // a fraction of the distance moved plus a floor (a cheap base: a few percent).
  double noisePerM = 0.03;                // sigma per metre moved
  double noiseFloorM = 0.001;             // metres
  double noisePerRad = 0.03;              // sigma of the rotation per radian turned
  double noiseFloorRad = 0.0005;          // radians (0.03 deg: a heading random walk of 0.16 deg/sqrt(s) at 30 Hz)
  // Fusion per eigen-motion of the view's structure (pipeline/tracking_quality.h): along an eigenvector with
  // conditioning c the tracked pose weighs c / (c + lambda), where lambda = (sigmaIcpM / sigma_odometry)^2 *
  // cFull: a view that constrains a motion like a fully furnished one (c = cFull) with a point noise of
  // sigmaIcpM per frame meets the odometry's sigma as an equal. Below minConditioning (a motion the view leaves
  // free: a corridor seen lengthwise) the odometry alone.
  double icpSigmaM = 0.002;               // metres: ICP's error along a well-constrained motion, per frame
  double fullConditioning = 0.05;         // a well-furnished view's conditioning (a corner: 0.1-0.3)
  double minConditioning = 0.003;         // below: the view does not fix the motion (wall-only views: <= 0.0025)
  // A wheel slip: the odometry's step is contradicted by the view along the motions it fixes by more than
  // this many sigmas (and at least slipFloorM): the step is not used. A step beyond the platform's limits is
  // a slip too.
  double slipSigmas = 5.0;
  double slipFloorM = 0.03;               // metres
  // When depth cannot track, the pose follows the odometry alone for at most this distance and time (state
  // `odometry`), then the frame is lost. The distance keeps the accumulated drift (noisePerM of it) inside
  // ICP's reach when the view returns.
  double maxDistanceM = 3.0;              // metres
  double maxTimeS = 10.0;                 // seconds
  // A relocalisation candidate farther than this from the odometry's pose (plus noisePerM of the distance
  // driven since depth last tracked) is refused: a corridor repeats itself, the wheels know which part it is.
  double relocaliseToleranceM = 0.5;      // metres
  // Stamps: the odometry is interpolated at a frame's stamp, extrapolated at most this far past its newest
  // sample, and not across a gap longer than maxGapS.
  double maxExtrapolationS = 0.05;
  double maxGapS = 0.5;
  // The wheels' systematic errors (distance scale, turn scale, yaw drift) are learnt online where the view fixes
  // the motion (odometry/odometry_calibration.h), from the evidence of about this many metres driven; 0: off.
  double calibrationWindowM = 20.0;       // metres
  // The odometry's tilt is absolute: a base on a floor (or one whose odometry is fused with an IMU's gravity)
  // does not drift in it as the view's chain of relative motions does. Every fused frame takes it as a measurement
  // with this sigma (the floor's bumps and the suspension: not a drift), so the tilt error stays bounded instead of
  // growing with the distance driven, and with it the height error a tilted heading drives. 0: off.
  double tiltSigmaDeg = 0.5;              // degrees, about the axes square to up
  // ... but only as good as the camera mount the odometry assumes: a mount off by e about the axes square to up
  // tilts the odometry's camera by 2 sin(psi / 2) e once the base has turned by psi from where the tilt was
  // anchored (a U-turn: twice the mount's error). Until the mount is learnt (odometry/mount_calibration.h) the
  // tilt's sigma grows with that chord times this (a mount measured by hand: a degree or two off). Held to
  // tilt_sigma_deg alone, a mount 2.5 degrees off rolled the map 4.5 degrees in a U-turn whose view left the roll
  // free, and the way back climbed 1.2 m (docs/odometry.md "The mount's tilt"). 0: the mount is taken as exact (and
  // not learnt, from the floor or the turns).
  double mountSigmaDeg = 2.0;             // degrees
  // Faults (odometry/wheel_faults.h): a disagreement between the wheels and a view that fixes the motion is
  // decided by the evidence of this long (a wheel slip is one step; a stall, a pick-up or wrong wheels last
  // seconds), nothing fused meanwhile; a fault ends when the wheels' steps agree with the view again for calmS.
  // 0: off, a disagreement is decided by one frame's inertia. Measured (docs/wheel-faults.md, twenty drives,
  // both controllers): on, the `good` frames more than 0.5 m off fall from 6518 to 664 (adaptive) and 6340 to
  // 1487 (DEFAULT), every fault-free drive stays posed; a carried robot is not relocalised yet.
  double disputeS = 0.3;                  // seconds
  // While the wheels are withheld (slipping) nothing holds the motions the view leaves free: facing an end wall,
  // the height slid 0.3 m in 20 frames. A base on its floor keeps its camera's height and tilt whatever its wheels
  // read, so ICP's solve weighs them (pipeline/icp_solve.h PlanarPrior, towards the last pose the view fixed in
  // agreement with the wheels) as firmly as a view with this structure conditioning would: above the per-pixel
  // noise floor of a free motion (0.0004-0.0025), well under a furnished view's (full_conditioning). 0: off.
  double planarPriorConditioning = 0.01;
  double calmS = 0.5;                     // seconds
  // A frame holds the map when its pair agreement is at least this fraction of the median of the recent
  // undisputed frames': below, the view does not fit the map where it is tracked (a robot set down elsewhere, a
  // runaway). Driving frames agree with 0.6-0.9 of the model, a view 9 m from where it is tracked with 0.1-0.45.
  double mapAgreementFraction = 0.5;
  // A frame the tracking rate skips takes the wheels' pose; it is the view's word (carries its state) only within
  // this time of the last frame the view fixed, and the next frame is tracked whatever the rate.
  double maxUncheckedS = 1.0;             // seconds
  // The odometry's stamps against the frames' (odometry/time_offset.h): a frame at stamp t is matched with the
  // odometry at t + timeOffsetS (a latency of 40 ms: 0.04), learnt online within timeOffsetRangeS of it (0: fixed).
  double timeOffsetS = 0.0;               // seconds
  double timeOffsetRangeS = 0.0;          // seconds (learning off by default: docs/wheel-faults.md)

  void read(ConfigReader& r);
  nlohmann::json toJson() const;
};

// The `odometry` section of a settings file (null: the defaults), read from `where`; throws sb::Error naming
// `where` and the key.
OdometryConfig odometryConfigFrom(const nlohmann::json& section, const std::string& where);

}  // namespace sb::odometry
