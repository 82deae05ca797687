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
//
// The floor shows the same tilt without turning (floor_up.h): its normal in the camera frame is the base's up.
// Once kMinFloorFrames frames showed a floor, the correction is the rotation taking the assumed up to their
// median up (component by component: a frame whose floor was a ramp's or a glimpse's does not move it), and it is
// preferred to the turns' (a corridor drive: a frame's floor within 0.02-0.2 degrees of the truth, the turns' axis
// a degree or more). Where no floor is seen (a view into a wall, a scene without one) the turns decide as before.

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "odometry/odometry_fusion.h"

namespace sb::odometry {

class MountCalibration {
 public:
  // A frame whose step the wheels and the view agree on: `viewStep` the view's rotation from the previous frame
  // (in that frame's camera frame), `raw` the wheels' step (in the frame of the mount they assume).
  void learn(const Eigen::Matrix3d& viewStep, const OdometryStep& raw);
  // A frame's floor up (floor_up.h), `assumedUp` the up of the mount the odometry assumes (OdometryStep::up as
  // reported), both in the camera frame.
  void floorSeen(const Eigen::Vector3d& floorUp, const Eigen::Vector3d& assumedUp);
  // Frames whose floor has been taken (floorSeen); the learner wants no more once kEnoughFloorFrames have.
  size_t floorFrames() const { return floorFrames_; }
  bool wantsFloor() const { return floorFrames_ < kEnoughFloorFrames; }
  // Where the correction comes from: "floor", "turns" or "" (none yet).
  const char* source() const;
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
    // The floor's part: the frames read (kEnoughFloorFrames: no more are), their spread, whether it decided.
    int32_t floorFrames = 0;
    double floorSpreadRad = 0.0;
    bool fromFloor = false;
  };
  State state() const {
    return {viewSum_, wheelSum_, diffSum_, diffSquares_, weights_, weightSquares_, turnRad_, standardError_,
            correction_, static_cast<int32_t>(floorFrames_), floorSpreadRad_, fromFloor_};
  }
  void restore(const State& s);

 private:
  static constexpr double kMinStepDeg = 0.5;   // per frame: below, the axis is ICP's noise
  static constexpr double kMaxAxisDeg = 5.0;   // the two axes further apart: not the same turn
  static constexpr double kMinTurnDeg = 90.0;   // the turning seen before the correction is applied
  static constexpr double kSignificance = 3.0;  // standard errors
  static constexpr size_t kMinFloorFrames = 30;     // a second of frames: a floor seen, not a glimpse
  static constexpr size_t kEnoughFloorFrames = 300;  // then the floor's mean holds; no more frames are read
  static constexpr double kFloorAgreeDeg = 1.0;     // the frames' median distance from their median up, at most
  std::vector<Eigen::Vector3d> floorUps_;  // the frames' floor ups (camera frame), at most kEnoughFloorFrames
  size_t floorFrames_ = 0;
  double floorSpreadRad_ = 0.0;  // the frames' median distance from the median up
  bool fromFloor_ = false;
  Eigen::Vector3d viewSum_ = Eigen::Vector3d::Zero(), wheelSum_ = Eigen::Vector3d::Zero();
  // Of the per-frame axis differences (view less wheels), weighted by the angle: sums for the mean's scatter.
  Eigen::Vector3d diffSum_ = Eigen::Vector3d::Zero();
  double diffSquares_ = 0.0, weights_ = 0.0, weightSquares_ = 0.0;
  double turnRad_ = 0.0;
  double standardError_ = 0.0;  // radians: of the mean axis difference, once kMinTurnDeg is seen
  Eigen::Matrix3d correction_ = Eigen::Matrix3d::Identity();
};

}  // namespace sb::odometry
