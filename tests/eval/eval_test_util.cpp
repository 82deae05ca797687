#include "tests/eval/eval_test_util.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>

namespace sb::test {

TimedPose makePose(double timestamp, const Eigen::Vector3d& position, const Eigen::Vector3d& axis,
                   double angleRad) {
  TimedPose p;
  p.timestamp = timestamp;
  p.T_camera_to_world.linear() = Eigen::AngleAxisd(angleRad, axis.normalized()).toRotationMatrix();
  p.T_camera_to_world.translation() = position;
  return p;
}

Trajectory helixTrajectory(size_t n, double rateHz) {
  constexpr double kRadiusM = 0.8, kClimbMPerRad = 0.05, kRadPerFrame = 0.03, kTiltRad = 0.3;
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(kTiltRad, Eigen::Vector3d(1, 1, 0).normalized()).matrix();
  Trajectory t;
  for (size_t i = 0; i < n; ++i) {
    const double a = kRadPerFrame * static_cast<double>(i);
    const Eigen::Vector3d p =
        tilt * Eigen::Vector3d(kRadiusM * std::cos(a), kRadiusM * std::sin(a), kClimbMPerRad * a);
    TimedPose pose = makePose(static_cast<double>(i) / rateHz, p, Eigen::Vector3d(0.2, 1.0, 0.3), 0.5 * a);
    pose.T_camera_to_world.linear() = pose.T_camera_to_world.linear() *
                                      Eigen::AngleAxisd(0.1 * std::sin(a), Eigen::Vector3d::UnitX()).matrix();
    t.push_back(pose);
  }
  return t;
}

Trajectory transformed(const Trajectory& t, const Eigen::Isometry3d& T) {
  Trajectory out = t;
  for (auto& p : out) p.T_camera_to_world = T * p.T_camera_to_world;
  return out;
}

double hornQuaternionRmse(const Trajectory& estimate, const Trajectory& groundTruth,
                          Eigen::Isometry3d* alignment) {
  if (estimate.size() != groundTruth.size() || estimate.empty()) throw std::invalid_argument("size mismatch");
  const double n = static_cast<double>(estimate.size());
  Eigen::Vector3d ce = Eigen::Vector3d::Zero(), cg = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < estimate.size(); ++i) {
    ce += estimate[i].position() / n;
    cg += groundTruth[i].position() / n;
  }
  // Horn (1987): S_ab = sum x_a y_b over centred pairs, x from the estimate, y from the ground truth.
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < estimate.size(); ++i) {
    S += (estimate[i].position() - ce) * (groundTruth[i].position() - cg).transpose();
  }
  const double sxx = S(0, 0), sxy = S(0, 1), sxz = S(0, 2), syx = S(1, 0), syy = S(1, 1), syz = S(1, 2),
               szx = S(2, 0), szy = S(2, 1), szz = S(2, 2);
  Eigen::Matrix4d N;
  N << sxx + syy + szz, syz - szy, szx - sxz, sxy - syx,  //
      syz - szy, sxx - syy - szz, sxy + syx, szx + sxz,   //
      szx - sxz, sxy + syx, -sxx + syy - szz, syz + szy,  //
      sxy - syx, szx + sxz, syz + szy, -sxx - syy + szz;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(N);
  const Eigen::Vector4d q = eig.eigenvectors().col(3);  // eigenvalues ascending: the last is the largest
  const Eigen::Matrix3d R = Eigen::Quaterniond(q(0), q(1), q(2), q(3)).normalized().toRotationMatrix();
  const Eigen::Vector3d t = cg - R * ce;
  double sumSq = 0.0;
  for (size_t i = 0; i < estimate.size(); ++i) {
    sumSq += (R * estimate[i].position() + t - groundTruth[i].position()).squaredNorm();
  }
  if (alignment) {
    alignment->setIdentity();
    alignment->linear() = R;
    alignment->translation() = t;
  }
  return std::sqrt(sumSq / n);
}

}  // namespace sb::test
