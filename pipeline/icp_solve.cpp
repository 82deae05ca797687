#include "pipeline/icp_solve.h"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace sb {

bool solveIcpUpdate(const TrackSums& sums, Twist& x) {
  x.setZero();
  if (sums[28] < kMinIcpInliers) return false;
  Eigen::Matrix<double, 6, 6> A;
  Twist b;
  int k = 7;
  for (int i = 0; i < 6; ++i) {
    b(i) = sums[1 + i];
    for (int j = i; j < 6; ++j) {
      A(i, j) = sums[k];
      A(j, i) = sums[k];
      ++k;
    }
  }
  if (!A.allFinite() || !b.allFinite()) return false;
  // Symmetric positive semi-definite: solve in the eigenbasis, dropping near-null directions.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(A);
  if (eig.info() != Eigen::Success) return false;
  const auto& values = eig.eigenvalues();
  const double largest = values.maxCoeff();
  if (!(largest > 0)) return false;
  const Twist projected = eig.eigenvectors().transpose() * b;
  Twist scaled;
  for (int i = 0; i < 6; ++i) scaled(i) = values(i) > kIcpEigenCutoff * largest ? projected(i) / values(i) : 0.0;
  x = eig.eigenvectors() * scaled;
  return x.allFinite();
}

Eigen::Isometry3d twistToTransform(const Twist& x) {
  const Eigen::Vector3d v = x.head<3>();
  const Eigen::Vector3d w = x.tail<3>();
  const double theta = w.norm();
  Eigen::Matrix3d W;
  W << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d V = Eigen::Matrix3d::Identity();
  if (theta > 1e-12) {
    R = Eigen::AngleAxisd(theta, w / theta).toRotationMatrix();
    const double t2 = theta * theta;
    V += (1 - std::cos(theta)) / t2 * W + (theta - std::sin(theta)) / (t2 * theta) * W * W;
  } else {
    R += W;
    V += 0.5 * W;
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = V * v;
  return T;
}

}  // namespace sb
