#include "pipeline/icp_solve.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

namespace sb {

namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

}  // namespace

void icpNormalEquations(const TrackSums& sums, Matrix6& A, Twist& b) {
  int k = 7;
  for (int i = 0; i < 6; ++i) {
    b(i) = sums[1 + i];
    for (int j = i; j < 6; ++j) {
      A(i, j) = sums[k];
      A(j, i) = sums[k];
      ++k;
    }
  }
}

bool normalisedNormalMatrix(const Matrix6& A, double inliers, const Eigen::Isometry3d& T_camera_to_world,
                            Matrix6& An, Matrix6& T) {
  // Jacobian row [n, p x n] about the origin -> [n, (p - c) x n] about the camera centre c: J_c = J M.
  Matrix6 M = Matrix6::Identity();
  M.block<3, 3>(0, 3) = skew(T_camera_to_world.translation());
  An = M.transpose() * A * M;
  const double translationTrace = An.block<3, 3>(0, 0).trace();
  const double rotationTrace = An.block<3, 3>(3, 3).trace();
  if (!(translationTrace > 0) || !(rotationTrace > 0)) return false;
  const double s = std::sqrt(translationTrace / rotationTrace);
  An.block<3, 3>(0, 3) *= s;
  An.block<3, 3>(3, 0) *= s;
  An.block<3, 3>(3, 3) *= s * s;
  An /= inliers;
  T = M;
  T.block<6, 3>(0, 3) *= s;
  return true;
}

namespace {

// Solves A x = b (A symmetric positive semi-definite) in A's eigenbasis, dropping near-null directions
// (eigenvalue below kIcpEigenCutoff of the largest) and those whose eigenvalue is below `holdBelow`.
bool solveInEigenbasis(const Matrix6& A, const Twist& b, double holdBelow, Twist& x) {
  Eigen::SelfAdjointEigenSolver<Matrix6> eig(A);
  if (eig.info() != Eigen::Success) return false;
  const auto& values = eig.eigenvalues();
  const double largest = values.maxCoeff();
  if (!(largest > 0)) return false;
  const Twist projected = eig.eigenvectors().transpose() * b;
  Twist scaled;
  for (int i = 0; i < 6; ++i)
    scaled(i) = values(i) >= holdBelow && values(i) > kIcpEigenCutoff * largest ? projected(i) / values(i) : 0.0;
  x = eig.eigenvectors() * scaled;
  return true;
}

}  // namespace

bool solveIcpUpdate(const TrackSums& sums, Twist& x) {
  x.setZero();
  if (sums[28] < kMinIcpInliers) return false;
  Matrix6 A;
  Twist b;
  icpNormalEquations(sums, A, b);
  if (!A.allFinite() || !b.allFinite()) return false;
  if (!solveInEigenbasis(A, b, -std::numeric_limits<double>::infinity(), x)) return false;
  return x.allFinite();
}

void addPlanarPrior(const PlanarPrior& prior, const Eigen::Isometry3d& T_camera_to_world, const Matrix6& T,
                    Matrix6& An, Twist& bn) {
  // In the motion basis x_n = (the camera centre's displacement, the rotation about it / s): a rotation weighs as
  // the displacement it makes at the view's depth (T's rotational columns carry s).
  const double s = T(3, 3);
  const double k = prior.conditioning;
  if (!(k > 0) || !(s > 0)) return;
  const Eigen::Vector3d u = prior.up.normalized();
  const Eigen::Matrix3d across = Eigen::Matrix3d::Identity() - u * u.transpose();  // the axes of a tilt
  // The height: the camera centre along up, to the target's.
  const double climb = u.dot(prior.target.translation() - T_camera_to_world.translation());
  // The tilt: the small rotation that takes the camera's up (as the target carries it) back to up.
  const Eigen::Vector3d carried = T_camera_to_world.linear() * (prior.target.linear().transpose() * u);
  const Eigen::Vector3d tilt = across * carried.cross(u);
  An.block<3, 3>(0, 0) += k * u * u.transpose();
  bn.head<3>() += k * u * climb;
  An.block<3, 3>(3, 3) += k * across;
  bn.tail<3>() += k * tilt / s;
}

bool solveIcpUpdateHolding(const TrackSums& sums, const Eigen::Isometry3d& T_camera_to_world, double holdBelow,
                           Twist& x, const PlanarPrior* prior) {
  const bool withPrior = prior && prior->conditioning > 0;
  if (!(holdBelow > 0) && !withPrior) return solveIcpUpdate(sums, x);
  x.setZero();
  const double inliers = sums[28];
  if (inliers < kMinIcpInliers) return false;
  Matrix6 A, An, T;
  Twist b;
  icpNormalEquations(sums, A, b);
  if (!A.allFinite() || !b.allFinite()) return false;
  // T^T A T x_n = T^T b, per inlier so that the eigenvalues are conditionings.
  if (!normalisedNormalMatrix(A, inliers, T_camera_to_world, An, T)) return false;
  Twist bn = T.transpose() * b / inliers;
  if (withPrior) addPlanarPrior(*prior, T_camera_to_world, T, An, bn);
  Twist xn;
  if (!solveInEigenbasis(An, bn, holdBelow > 0 ? holdBelow : -std::numeric_limits<double>::infinity(), xn))
    return false;
  x = T * xn;
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

Twist transformToTwist(const Eigen::Isometry3d& T) {
  const Eigen::AngleAxisd turn(T.linear());
  const double theta = turn.angle();
  const Eigen::Vector3d w = theta * turn.axis();
  // V^-1 = I - W/2 + c W^2 with c = (1 - theta sin(theta) / (2 (1 - cos(theta)))) / theta^2; below 1e-3 rad its
  // series (1 - cos(theta) cancels to nothing in doubles near 0).
  const double t2 = theta * theta;
  const double c = theta < 1e-3 ? 1.0 / 12.0 + t2 / 720.0
                                : (1.0 - theta * std::sin(theta) / (2.0 * (1.0 - std::cos(theta)))) / t2;
  const Eigen::Matrix3d W = skew(w);
  const Eigen::Matrix3d Vinv = Eigen::Matrix3d::Identity() - 0.5 * W + c * W * W;
  Twist x;
  x << Vinv * T.translation(), w;
  return x;
}

}  // namespace sb
