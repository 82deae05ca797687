#include "ros/pose_covariance.h"

#include <Eigen/Geometry>

namespace sb::ros_bridge {

namespace {

// The camera axis a `weakest_motion` name stands for: 0-2 translation x, y, z; 3-5 rotation about them;
// -1 when absent or unknown (then every axis counts as weak).
int weakAxis(const std::string& name) {
  static const char* const kNames[] = {"tx", "ty", "tz", "rx", "ry", "rz"};
  for (int i = 0; i < 6; ++i)
    if (name == kNames[i]) return i;
  return -1;
}

}  // namespace

Covariance6 poseCovariance(const PoseReport& pose, const CovarianceConfig& config) {
  Eigen::Matrix<double, 6, 1> sigma;
  const auto fill = [&](const StateSigma& s) { sigma << s.positionM, s.positionM, s.positionM,
                                                        s.rotationRad, s.rotationRad, s.rotationRad; };
  fill(config.lost);  // a state this switch does not know says the least
  switch (pose.state) {
    case TrackingState::good: fill(config.good); break;
    case TrackingState::relocalised: fill(config.relocalised); break;
    case TrackingState::lost: fill(config.lost); break;
    case TrackingState::odometry:  // grows with the distance driven on the wheels alone
      fill(StateSigma{config.odometry.positionM + config.odometryDriftPerM * pose.odometryDriftM,
                      config.odometry.rotationRad + config.odometryDriftPerM * pose.odometryDriftM});
      break;
    case TrackingState::weak: {
      fill(config.weak);
      const int axis = weakAxis(pose.weakestMotion);
      for (int i = 0; i < 6; ++i)
        if (axis < 0 || axis == i) sigma[i] = i < 3 ? config.weakAxis.positionM : config.weakAxis.rotationRad;
      break;
    }
  }
  // Diagonal in the camera's axes; rotate both blocks into the parent frame: C = R D R^T.
  const Eigen::Quaterniond q(pose.quaternion[3], pose.quaternion[0], pose.quaternion[1], pose.quaternion[2]);
  Eigen::Matrix<double, 6, 6> rotate = Eigen::Matrix<double, 6, 6>::Zero();
  rotate.topLeftCorner<3, 3>() = q.normalized().toRotationMatrix();
  rotate.bottomRightCorner<3, 3>() = rotate.topLeftCorner<3, 3>();
  const Eigen::Matrix<double, 6, 6> cov =
      rotate * Eigen::Matrix<double, 6, 1>(sigma.cwiseProduct(sigma)).asDiagonal() * rotate.transpose();
  Covariance6 out{};
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) out[static_cast<size_t>(r * 6 + c)] = cov(r, c);
  return out;
}

}  // namespace sb::ros_bridge
