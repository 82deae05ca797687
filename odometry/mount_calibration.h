#pragma once
// The camera mount the odometry assumes, corrected online from the view (issue 52; docs/wheel-faults.md).
// Each odometry sample is the base's pose composed with a mount (T_camera_to_odom); a mount measured a degree or
// two off tilts the axis the wheels turn about as the camera sees it. Straight driving does not show it, but
// every turn does: after a U-turn the odometry's tilt is off by twice the mount's error, and held to it as an
// absolute measurement (tilt_sigma_deg) the map leans and the height drifts a metre over a corridor.
//
// A turn of the base is a rotation about one axis. The view sees it about the true axis (in the camera frame),
// the odometry about the mount-turned one; the rotation that takes the second to the first is the mount's error
// about the axes square to the turns (hand-eye calibration of a rotation, e.g. Tsai and Lenz, IEEE T-RA 1989,
// reduced to the one axis a planar base turns about). Its turn about that axis does not change a turn and is
// not learnt here. Evidence: the axes of the frames whose view fixes every rotation, weighted by their angle;
// the correction applies once kMinTurnDeg of such turning is seen and the mean axis difference is at least
// kSignificance of its standard errors (ICP's axis of a 3-degree step scatters by a degree or more: 24 degrees
// of turning on a drive without error gave 1.2 degrees).

#include <Eigen/Geometry>

#include "odometry/odometry_fusion.h"

namespace sb::odometry {

class MountCalibration {
 public:
  // A frame whose step the wheels and the view agree on: `viewStep` the view's rotation from the previous frame
  // (in that frame's camera frame), `raw` the wheels' step (in the frame of the mount they assume).
  void learn(const Eigen::Matrix3d& viewStep, const OdometryStep& raw);
  // The rotation E with T_camera_to_odom(true) = T_camera_to_odom(assumed) * E^-1 (identity until enough turns).
  const Eigen::Matrix3d& correction() const { return correction_; }
  // The wheels' step in the true camera frame: E delta E^-1, its up axis E up.
  OdometryStep correct(const OdometryStep& raw) const;
  // The correction's angle (degrees) and the turning seen (degrees).
  double errorDeg() const;
  double turnSeenDeg() const { return turnRad_ * 180.0 / 3.14159265358979323846; }
  // How far the mount's tilt may still be off (degrees): `priorDeg` (odometry_config.h mount_sigma_deg) until
  // kMinTurnDeg of turning is seen, then the significance bound of what was learnt, at most `priorDeg`.
  double sigmaDeg(double priorDeg) const;

  // What was learnt, whole (a map store keeps it for the next run, runtime/kept_odometry.h).
  struct State {
    Eigen::Vector3d viewSum = Eigen::Vector3d::Zero(), wheelSum = Eigen::Vector3d::Zero();
    Eigen::Vector3d diffSum = Eigen::Vector3d::Zero();
    double diffSquares = 0.0, weights = 0.0, weightSquares = 0.0, turnRad = 0.0, standardError = 0.0;
    Eigen::Matrix3d correction = Eigen::Matrix3d::Identity();
  };
  State state() const {
    return {viewSum_, wheelSum_, diffSum_, diffSquares_, weights_, weightSquares_, turnRad_, standardError_, correction_};
  }
  void restore(const State& s);

 private:
  static constexpr double kMinStepDeg = 0.5;   // per frame: below, the axis is ICP's noise
  static constexpr double kMaxAxisDeg = 5.0;   // the two axes further apart: not the same turn
  static constexpr double kMinTurnDeg = 90.0;   // the turning seen before the correction is applied
  static constexpr double kSignificance = 3.0;  // standard errors
  Eigen::Vector3d viewSum_ = Eigen::Vector3d::Zero(), wheelSum_ = Eigen::Vector3d::Zero();
  // Of the per-frame axis differences (view less wheels), weighted by the angle: sums for the mean's scatter.
  Eigen::Vector3d diffSum_ = Eigen::Vector3d::Zero();
  double diffSquares_ = 0.0, weights_ = 0.0, weightSquares_ = 0.0;
  double turnRad_ = 0.0;
  double standardError_ = 0.0;  // radians: of the mean axis difference, once kMinTurnDeg is seen
  Eigen::Matrix3d correction_ = Eigen::Matrix3d::Identity();
};

}  // namespace sb::odometry
