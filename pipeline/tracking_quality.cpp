#include "pipeline/tracking_quality.h"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "pipeline/icp_solve.h"

namespace sb {

namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;

Mat6 normalMatrix(const TrackSums& sums) {
  Mat6 A;
  int k = 7;
  for (int i = 0; i < 6; ++i)
    for (int j = i; j < 6; ++j) {
      A(i, j) = sums[k];
      A(j, i) = sums[k];
      ++k;
    }
  return A;
}

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

}  // namespace

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
  Mat6 A = normalMatrix(sums);
  if (inliers < kMinIcpInliers || !A.allFinite()) return q;
  // Jacobian row [n, p x n] about the origin -> [n, (p - c) x n] about the camera centre c: J_c = J M.
  Mat6 M = Mat6::Identity();
  M.block<3, 3>(0, 3) = skew(T_camera_to_world.translation());
  A = M.transpose() * A * M;
  const double translationTrace = A.block<3, 3>(0, 0).trace();
  const double rotationTrace = A.block<3, 3>(3, 3).trace();
  if (!(translationTrace > 0) || !(rotationTrace > 0)) return q;
  const double s = std::sqrt(translationTrace / rotationTrace);
  A.block<3, 3>(0, 3) *= s;
  A.block<3, 3>(3, 0) *= s;
  A.block<3, 3>(3, 3) *= s * s;
  A /= inliers;
  Eigen::SelfAdjointEigenSolver<Mat6> eig(A);
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
