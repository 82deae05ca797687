#include "pipeline/tracking_quality.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "pipeline/icp_solve.h"

namespace sb {

const char* weakDirectionName(WeakDirection d) {
  static const char* const names[] = {"tx", "ty", "tz", "rx", "ry", "rz"};
  return names[static_cast<int>(d)];
}

namespace {

// The smallest eigenvalue of J^T J (from `sums`) normalised per inlier (tracking_quality.h) and the camera
// axis its eigenvector lies along most; false when the matrix is not usable.
bool weakestMotion(const TrackSums& sums, double inliers, const Eigen::Isometry3d& T_camera_to_world,
                   double& value, WeakDirection& axis, Matrix6& An, Matrix6& T) {
  Matrix6 A;
  Twist b;
  icpNormalEquations(sums, A, b);
  if (!A.allFinite()) return false;
  if (!normalisedNormalMatrix(A, inliers, T_camera_to_world, An, T)) return false;
  Eigen::SelfAdjointEigenSolver<Matrix6> eig(An);
  if (eig.info() != Eigen::Success) return false;
  value = std::max(0.0, eig.eigenvalues()(0));  // ascending order
  // The weakest motion in camera axes: translation part and rotation part rotated into the camera frame.
  const Eigen::Matrix<double, 6, 1> v = eig.eigenvectors().col(0);
  const Eigen::Matrix3d toCamera = T_camera_to_world.linear().transpose();
  Eigen::Matrix<double, 6, 1> camera;
  camera << toCamera * v.head<3>(), toCamera * v.tail<3>();
  Eigen::Index largest = 0;
  camera.cwiseAbs().maxCoeff(&largest);
  axis = static_cast<WeakDirection>(largest);
  return true;
}

}  // namespace

TrackingQuality trackingQuality(const TrackSums& icp, const TrackSums& blocks,
                                const Eigen::Isometry3d& T_camera_to_world, double minConditioning) {
  TrackingQuality q;
  q.known = true;
  q.constrained = false;
  const double inliers = icp[28];
  if (inliers < kMinIcpInliers) return q;
  WeakDirection unused = WeakDirection::tx;
  Matrix6 An, T;
  if (!weakestMotion(icp, inliers, T_camera_to_world, q.icpConditioning, unused, An, T)) return q;
  if (!weakestMotion(blocks, inliers, T_camera_to_world, q.conditioning, q.weakest, An, T)) return q;
  q.constrained = q.conditioning >= minConditioning;
  q.structure = An;
  q.basis = T;
  return q;
}

Twist blendByStructure(const TrackingQuality& q, const Twist& previous, const Twist& measured, double lambda) {
  if (!(lambda > 0) || !q.known || q.structure.isZero()) return measured;
  Eigen::SelfAdjointEigenSolver<Matrix6> eig(q.structure);
  if (eig.info() != Eigen::Success) return measured;
  const Eigen::FullPivLU<Matrix6> basis(q.basis);
  if (!basis.isInvertible()) return measured;
  const Twist change = eig.eigenvectors().transpose() * basis.solve(measured - previous);
  Twist kept;
  for (int i = 0; i < 6; ++i) {
    const double c = std::max(0.0, eig.eigenvalues()(i));
    kept(i) = change(i) * c / (c + lambda);
  }
  return previous + q.basis * (eig.eigenvectors() * kept);
}

}  // namespace sb
