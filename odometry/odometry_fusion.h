#pragma once
// The odometry meets the view (docs/odometry.md): the step the wheels report between two frames,
// the platform's physics, and the tracked pose fused with the odometry's prediction per eigen-motion of the
// view's structure, after the degeneracy-aware update of Zhang, Kaess and Singh (ICRA 2016: "On degeneracy of
// optimization-based state estimation problems"): along a motion the view fixes the tracked pose wins, along
// one it leaves free the prediction does, and between the two they weigh by their noise.

#include <Eigen/Geometry>
#include <optional>
#include <string>

#include "odometry/odometry_config.h"
#include "odometry/odometry_track.h"
#include "pipeline/icp_solve.h"
#include "pipeline/tracking_quality.h"

namespace sb::odometry {

// The odometry's motion between two frames' stamps.
struct OdometryStep {
  Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();  // in the earlier camera's frame: pose(t0)^-1 pose(t1)
  double dt = 0.0;        // seconds
  double sigmaM = 0.0;    // its translation's noise (metres), from the samples' covariance or the config
  double sigmaRad = 0.0;  // its rotation's noise (radians)
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  // the odometry frame's up axis (REP 103: z) in the earlier camera's frame
  double distanceM() const { return delta.translation().norm(); }
};

// The step between t0 and t1, or nullopt with `why` when the track has no pose at either stamp.
std::optional<OdometryStep> stepBetween(const OdometryTrack& track, double t0, double t1, const OdometryConfig& c,
                                        std::string& why);

// `step`'s noise widened to that of the wheels' whole interval since the view last fixed the pose (`since`: the
// step from that frame's stamp). The frames between took the wheels' poses (skipped by the tracking rate, or dead
// reckoning in state `odometry`), so the prediction they lead to is as uncertain as all of it. Held to one step's
// noise it outweighed the view: 2-3 frames of a base's scale and turn errors taken as certain, and after a covered
// lens the view's correction of 2 s of drift was refused as a slip (docs/odometry.md).
void widenNoise(OdometryStep& step, const OdometryStep& since);

// `predicted` (a camera pose in the world frame) turned to the tilt of `odometry` (the odometry's own camera pose,
// in the world frame), `up` the odometry frame's up axis in the world frame: it turns about the camera centre and
// about an axis square to up, so the position and the heading stay.
Eigen::Isometry3d levelled(const Eigen::Isometry3d& predicted, const Eigen::Isometry3d& odometry,
                           const Eigen::Vector3d& up);

// A body's velocity between two frames: `linear` m/s in the world frame, `angular` the rotation vector per second
// in the earlier frame's camera axes (a robot's turn about its up axis keeps it).
struct Velocity {
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();
};
// The velocity that takes `previous` to `pose` in `dt` > 0 seconds.
Velocity velocityBetween(const Eigen::Isometry3d& previous, const Eigen::Isometry3d& pose, double dt);

// Of a view and wheels that disagree (the view's pose `tracked`, the wheels' `predicted`, both from `previous`
// `dt` seconds ago), why the view is the wrong one, or "" when it is not shown to be: a body keeps its velocity
// (`last`), so of the two motions the one that departs further from it within the frame is wrong. A wheel slip is
// the wheels' jump; a view that matched the model elsewhere (a runaway) is the view's. Both the translation and
// the turn: a body keeps its turn rate as it keeps its speed, and a view facing a wall at a U-turn can swing
// 7-12 degrees in one frame from the turn the wheels report while its position moves a few centimetres (a
// held-out drive: taken as the wheels slipping, the run was lost). A departure of the view below `floorM` (metres
// in one frame; the same number as radians for the turn, 1.7 deg at 0.03) is within what tracking shows anyway.
// The view's turn is judged the wrong one only where the wheels' translation does not depart further than the
// view's. No last velocity or dt <= 0: "".
std::string viewBreaksInertia(const Eigen::Isometry3d& previous, const Eigen::Isometry3d& tracked,
                              const Eigen::Isometry3d& predicted, double dt, const std::optional<Velocity>& last,
                              double floorM);

// Why a camera motion from `previous` to `pose` in `dt` seconds is one the platform cannot make (speed, turn
// rate, or acceleration against `previousVelocity`, m/s in the world frame), or "" when it can. dt <= 0: "".
std::string implausibleMotion(const OdometryConfig& c, const Eigen::Isometry3d& previous,
                              const Eigen::Isometry3d& pose, double dt,
                              const std::optional<Eigen::Vector3d>& previousVelocity);

// How well the view fixes the world-frame motion `d` (a twist): the structure's Rayleigh quotient along it, the
// conditioning of tracking_quality.h for that one motion (0 when the structure is not known).
double conditioningAlong(const TrackingQuality& q, const Twist& d);

struct Fusion {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // the fused pose (the tracked one when rejected)
  bool rejected = false;      // the view contradicts the odometry along the motions it fixes (a wheel slip)
  double disagreementM = 0.0;   // along those motions: translation (metres) ...
  double disagreementRad = 0.0;  // ... and rotation (radians)
  // The prediction moved by the view along those motions (the prediction itself when the view fixes none).
  Eigen::Isometry3d viewed = Eigen::Isometry3d::Identity();
  std::string why;            // when rejected
  // The fused pose's covariance (world-frame twists of icp_solve.h, a left perturbation), when fused: the next
  // frame's prior is this plus the wheels' step noise (`priorCovariance` of fuseWithOdometry).
  std::optional<Matrix6> covariance;
};

// The odometry's absolute tilt (tilt_sigma_deg): its camera pose and its up axis, both in the world frame.
struct Level {
  Eigen::Isometry3d odometry = Eigen::Isometry3d::Identity();
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  double sigmaRad = 0.0;  // the tilt's sigma at this frame (tiltSigma, widened by the mount's: levelSigmaRad)
};

// The absolute tilt's sigma (radians) once the base has turned by `turnRad` from the frame the tilt was anchored
// at: tilt_sigma_deg and, added in quadrature, the mount's tilt error `mountSigmaDeg` times the chord
// 2 sin(turn / 2) (odometry_config.h mount_sigma_deg).
double levelSigmaRad(double tiltSigmaDeg, double mountSigmaDeg, double turnRad);

// `previous`: the last frame's final pose; `tracked`: this frame's ICP result; `predicted` = previous *
// step.delta; `quality`: the tracked frame's (its structure and basis). Without a known structure the view
// cannot say which motions it fixes: the tracked pose, not rejected. ICP registers against the map, whose error
// does not grow with the compute size as a frame-to-frame match's would: icp_sigma_m holds at every csr
// (measured on the corridor drive, adaptive with odometry: 6.7 cm; icp_sigma_m scaled by csr 7.2, by sqrt(csr)
// 7.7; a fixed 5 mm 5.7 but DEFAULT's 4.5 -> 9.3; 1 mm 8.4, 10 mm 16.4).
// With `level` the odometry's tilt is a third measurement, with its own sigma (tilt_sigma_deg). Its height is not:
// held to the odometry's height the fused pose pitched to meet the map's floor and ran away (docs/odometry.md).
// `previousCovariance`: the uncertainty of `previous` (Fusion::covariance of the frame before, when that frame was
// fused): the prediction is as uncertain as the previous pose plus the step, as a Kalman filter's prior is.
// Without it the previous pose counts as exact and the prediction as uncertain as one step: ICP registers
// against the map (an absolute measurement) and the wheels report increments, so a wheel bias b per frame left a
// standing error of about b (1 - K) / K, K the view's share of one frame, which for the heading of a corridor
// seen lengthwise is small (a 0.3 deg/s gyro drift bent the map 1.4-2.3 deg, 0.25-0.5 m across at 15 m; without
// odometry 0.04 m: docs/odometry.md). With it, K grows to the filter's steady state.
Fusion fuseWithOdometry(const TrackingQuality& quality, const Eigen::Isometry3d& previous,
                        const Eigen::Isometry3d& tracked, const Eigen::Isometry3d& predicted,
                        const OdometryStep& step, const OdometryConfig& c,
                        const std::optional<Level>& level = std::nullopt,
                        const std::optional<Matrix6>& previousCovariance = std::nullopt);

}  // namespace sb::odometry
