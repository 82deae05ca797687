#include "pipeline/tracking_quality.h"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "pipeline/icp_solve.h"

namespace sb {

const char* weakDirectionName(WeakDirection d) {
  static const char* const names[] = {"tx", "ty", "tz", "rx", "ry", "rz"};
  return names[static_cast<int>(d)];
}

TrackingQuality trackingQuality(const TrackSums& sums, const Eigen::Isometry3d& T_camera_to_world,
                                double minConditioning) {
  TrackingQuality q;
  q.known = true;
  q.constrained = false;
  const double inliers = sums[28];
  Matrix6 A, An, T;
  Twist b;
  icpNormalEquations(sums, A, b);
  if (inliers < kMinIcpInliers || !A.allFinite()) return q;
  if (!normalisedNormalMatrix(A, inliers, T_camera_to_world, An, T)) return q;
  Eigen::SelfAdjointEigenSolver<Matrix6> eig(An);
  if (eig.info() != Eigen::Success) return q;
  q.conditioning = std::max(0.0, eig.eigenvalues()(0));  // ascending order
  // The weakest motion in camera axes: translation part and rotation part rotated into the camera frame.
  const Eigen::Matrix<double, 6, 1> v = eig.eigenvectors().col(0);
  const Eigen::Matrix3d toCamera = T_camera_to_world.linear().transpose();
  Eigen::Matrix<double, 6, 1> camera;
  camera << toCamera * v.head<3>(), toCamera * v.tail<3>();
  Eigen::Index largest = 0;
  camera.cwiseAbs().maxCoeff(&largest);
  q.weakest = static_cast<WeakDirection>(largest);
  q.constrained = q.conditioning >= minConditioning;
  return q;
}

}  // namespace sb
