#include "odometry/odometry_fusion.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "odometry/format_numbers.h"
#include "pipeline/icp_solve.h"

namespace sb::odometry {

namespace {

constexpr double kDegPerRad = 180.0 / 3.14159265358979323846;

double angleOf(const Eigen::Matrix3d& R) { return Eigen::AngleAxisd(R).angle(); }

Eigen::Isometry3d rigid(const Eigen::Isometry3d& T) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = Eigen::Quaterniond(T.rotation()).normalized().toRotationMatrix();
  out.translation() = T.translation();
  return out;
}

}  // namespace

double conditioningAlong(const TrackingQuality& q, const Twist& d) {
  const Twist x = q.basis.fullPivLu().solve(d);
  const double n = x.squaredNorm();
  return n > 0 && std::isfinite(n) ? std::max(0.0, x.dot(q.structure * x) / n) : 0.0;
}

std::optional<OdometryStep> stepBetween(const OdometryTrack& track, double t0, double t1, const OdometryConfig& c,
                                        std::string& why) {
  const auto a = track.poseAt(t0, c.maxGapS, c.maxExtrapolationS);
  const auto b = track.poseAt(t1, c.maxGapS, c.maxExtrapolationS);
  if (!a || !b) {
    why = formatNumbers("no odometry at %.3f s (newest sample %.3f s)", a ? t1 : t0, track.newestStamp().value_or(NAN));
    return std::nullopt;
  }
  OdometryStep s;
  s.delta = rigid(a->inverse() * *b);
  s.dt = t1 - t0;
  s.up = a->linear().transpose() * Eigen::Vector3d::UnitZ();
  const double angle = angleOf(s.delta.linear());
  s.sigmaM = c.noiseFloorM + c.noisePerM * s.distanceM();
  s.sigmaRad = c.noiseFloorRad + c.noisePerRad * angle;
  // A stated covariance (the source's, per sample) grows with the pose; the step's share is their difference
  // when it is larger than the config's model.
  const auto ca = track.covarianceAt(t0), cb = track.covarianceAt(t1);
  if (ca && cb) {
    const double dPos = (cb->topLeftCorner<3, 3>().trace() - ca->topLeftCorner<3, 3>().trace());
    const double dRot = (cb->bottomRightCorner<3, 3>().trace() - ca->bottomRightCorner<3, 3>().trace());
    if (dPos > 0) s.sigmaM = std::max(s.sigmaM, std::sqrt(dPos));
    if (dRot > 0) s.sigmaRad = std::max(s.sigmaRad, std::sqrt(dRot));
  }
  return s;
}

void widenNoise(OdometryStep& step, const OdometryStep& since) {
  step.sigmaM = std::max(step.sigmaM, since.sigmaM);
  step.sigmaRad = std::max(step.sigmaRad, since.sigmaRad);
}

double levelSigmaRad(double tiltSigmaDeg, double mountSigmaDeg, double turnRad) {
  const double chord = 2.0 * std::abs(std::sin(0.5 * turnRad));
  return std::hypot(tiltSigmaDeg, chord * mountSigmaDeg) / kDegPerRad;
}

Eigen::Isometry3d levelled(const Eigen::Isometry3d& predicted, const Eigen::Isometry3d& odometry,
                           const Eigen::Vector3d& up) {
  const Eigen::Vector3d a = predicted.linear().transpose() * up;  // up in the camera frame, as predicted
  const Eigen::Vector3d b = odometry.linear().transpose() * up;   // and as the odometry has it
  const Eigen::AngleAxisd tilt(Eigen::Quaterniond::FromTwoVectors(a, b));
  Eigen::Isometry3d out = predicted;
  out.linear() = predicted.linear() * tilt.toRotationMatrix().transpose();
  return rigid(out);
}

std::string implausibleMotion(const OdometryConfig& c, const Eigen::Isometry3d& previous,
                              const Eigen::Isometry3d& pose, double dt,
                              const std::optional<Eigen::Vector3d>& previousVelocity) {
  if (!(dt > 0)) return {};
  const Eigen::Vector3d v = (pose.translation() - previous.translation()) / dt;
  if (v.norm() > c.maxSpeedMPerS)
    return formatNumbers("moved at %.2f m/s, beyond the platform's %.2f m/s", v.norm(), c.maxSpeedMPerS);
  const double turn = angleOf(previous.linear().transpose() * pose.linear()) * kDegPerRad / dt;
  if (turn > c.maxTurnRateDegPerS)
    return formatNumbers("turned at %.0f deg/s, beyond the platform's %.0f deg/s", turn, c.maxTurnRateDegPerS);
  if (previousVelocity) {
    const double a = (v - *previousVelocity).norm() / dt;
    if (a > c.maxAccelerationMPerS2)
      return formatNumbers("accelerated at %.1f m/s^2, beyond the platform's %.1f m/s^2", a, c.maxAccelerationMPerS2);
  }
  return {};
}

Velocity velocityBetween(const Eigen::Isometry3d& previous, const Eigen::Isometry3d& pose, double dt) {
  Velocity v;
  v.linear = (pose.translation() - previous.translation()) / dt;
  const Eigen::AngleAxisd turn(previous.linear().transpose() * pose.linear());
  v.angular = turn.axis() * turn.angle() / dt;
  return v;
}

std::string viewBreaksInertia(const Eigen::Isometry3d& previous, const Eigen::Isometry3d& tracked,
                              const Eigen::Isometry3d& predicted, double dt, const std::optional<Velocity>& last,
                              double floorM) {
  if (!last || !(dt > 0)) return {};
  const Eigen::Vector3d& from = previous.translation();
  const double departView = ((tracked.translation() - from) / dt - last->linear).norm() * dt;
  const double departWheels = ((predicted.translation() - from) / dt - last->linear).norm() * dt;
  if (departView > departWheels && departView >= floorM)
    return formatNumbers("the view departs %.3f m from the last velocity in one frame, the odometry %.3f m: the view is wrong",
                         departView, departWheels);
  // The turn the last turn rate carries on to, and how far each side's orientation is from it.
  const double rate = last->angular.norm();
  const Eigen::Matrix3d kept =
      previous.linear() *
      (rate > 0 ? Eigen::AngleAxisd(rate * dt, last->angular / rate).toRotationMatrix() : Eigen::Matrix3d::Identity());
  const double turnView = angleOf(kept.transpose() * tracked.linear());
  const double turnWheels = angleOf(kept.transpose() * predicted.linear());
  if (turnView > turnWheels && turnView >= floorM && departWheels <= std::max(departView, floorM))
    return formatNumbers("the view turns %.2f deg from the last turn rate in one frame, the odometry %.2f deg: the view is wrong",
                         turnView * kDegPerRad, turnWheels * kDegPerRad);
  return {};
}

Fusion fuseWithOdometry(const TrackingQuality& q, const Eigen::Isometry3d& previous, const Eigen::Isometry3d& tracked,
                        const Eigen::Isometry3d& predicted, const OdometryStep& step, const OdometryConfig& c,
                        const std::optional<Level>& level, const std::optional<Matrix6>& previousCovariance) {
  Fusion f;
  f.pose = tracked;
  f.viewed = predicted;
  if (!q.known || q.structure.isZero()) return f;
  Eigen::SelfAdjointEigenSolver<Matrix6> eig(q.structure);
  const Eigen::FullPivLU<Matrix6> basis(q.basis);
  if (eig.info() != Eigen::Success || !basis.isInvertible()) return f;
  // Steps in the world frame (the twists of icp_solve.h): the pose is exp(step) * previous.
  const Twist odo = transformToTwist(rigid(predicted * previous.inverse()));
  const Twist icp = transformToTwist(rigid(tracked * previous.inverse()));
  if (!odo.allFinite() || !icp.allFinite()) return f;
  const Twist change = eig.eigenvectors().transpose() * basis.solve(icp - odo);
  // Information in the motion basis (x_n: the camera centre's translation in metres, rotations times the
  // view's lever 1/s, tracking_quality.h). The view's: along an eigen-motion with conditioning c, c / (sigma_icp^2
  // * c_full) (a view as furnished as c_full fixes a motion to sigma_icp), none below min_conditioning. The
  // odometry's: its translation and rotation noise, the rotation's at the same lever.
  const double s = std::abs(q.basis(3, 3));
  Twist viewInfo, fixedPart;
  for (int i = 0; i < 6; ++i) {
    const double ci = std::max(0.0, eig.eigenvalues()(i));
    const bool fixes = ci >= c.minConditioning;
    viewInfo(i) = fixes ? ci / (c.icpSigmaM * c.icpSigmaM * c.fullConditioning) : 0.0;
    fixedPart(i) = fixes ? change(i) : 0.0;
  }
  Twist odoInfo;
  odoInfo.head<3>().setConstant(1.0 / std::pow(std::max(step.sigmaM, 1e-9), 2));
  odoInfo.tail<3>().setConstant(s * s / std::pow(std::max(step.sigmaRad, 1e-9), 2));
  const Matrix6& E = eig.eigenvectors();
  const Matrix6 view = E * viewInfo.asDiagonal() * E.transpose();
  Matrix6 prior = odoInfo.asDiagonal();
  if (previousCovariance && previousCovariance->allFinite()) {
    // The previous pose's covariance in this frame's motion basis, plus the step's: the prior's information.
    // In all six motions: held to one step's noise in the tilt and the height (the floor holds them) and carried
    // in the plane only, the heading stayed nearer the wheels' (the view sees it together with the tilt): on the
    // plain, plain2, stall2 and latency drives (320x240) the worst errors were 0.26, 0.11, 0.46, 0.22 m, carried
    // in all six 0.20, 0.20, 0.30, 0.21 m (docs/odometry.md).
    const Matrix6 inverseBasis = basis.inverse();
    Matrix6 cov = inverseBasis * *previousCovariance * inverseBasis.transpose();
    cov.diagonal() += odoInfo.cwiseInverse();
    const Matrix6 info = cov.ldlt().solve(Matrix6::Identity());
    if (info.allFinite()) prior = 0.5 * (info + info.transpose());
  }
  Matrix6 all = view + prior;
  Twist pull = view * (E * change);
  if (level && c.tiltSigmaDeg > 0) {
    // The odometry's tilt as measured (relative to the prediction): rotations about the axes square to up, in the
    // motion basis (world axes; rotations about the camera centre at the view's lever).
    const Eigen::Vector3d& u = level->up;
    const Twist toLevel = basis.solve(transformToTwist(rigid(levelled(predicted, level->odometry, u) *
                                                             predicted.inverse())));
    const double tiltRad = level->sigmaRad > 0.0 ? level->sigmaRad : c.tiltSigmaDeg / kDegPerRad;
    Matrix6 info = Matrix6::Zero();
    info.bottomRightCorner<3, 3>() = (Eigen::Matrix3d::Identity() - u * u.transpose()) * s * s / (tiltRad * tiltRad);
    if (toLevel.allFinite()) {
      all += info;
      pull += info * toLevel;
    }
  }
  // The fused motion: the odometry's plus the shares of the view's (and the tilt's) differences their information
  // earns.
  const Twist keptN = all.ldlt().solve(pull);
  // How far the view moves the prediction along the motions it fixes: a slip when beyond the odometry's noise.
  const Eigen::Isometry3d viewed = rigid(twistToTransform(odo + q.basis * (eig.eigenvectors() * fixedPart)) * previous);
  f.viewed = viewed;
  f.disagreementM = (viewed.translation() - predicted.translation()).norm();
  f.disagreementRad = angleOf(predicted.linear().transpose() * viewed.linear());
  const double gateM = std::max(c.slipSigmas * step.sigmaM, c.slipFloorM);
  const double gateRad = std::max(c.slipSigmas * step.sigmaRad, c.slipFloorM);  // slipFloorM as radians: 1.7 deg
  if (f.disagreementM > gateM || f.disagreementRad > gateRad) {
    f.rejected = true;
    f.why = formatNumbers("the view moves the odometry's prediction by %.3f m, %.2f deg along the motions it fixes",
                   f.disagreementM, f.disagreementRad * kDegPerRad);
    return f;
  }
  const Twist fused = odo + q.basis * keptN;
  if (fused.allFinite()) f.pose = rigid(twistToTransform(fused) * previous);
  // The fused pose's covariance, in world twists; each motion's variance at most kMaxVariance (a motion the view
  // never fixes: its prior stays finite).
  constexpr double kMaxVariance = 1.0;
  Matrix6 cov = q.basis * all.ldlt().solve(Matrix6::Identity()) * q.basis.transpose();
  for (int i = 0; i < 6; ++i)
    if (cov(i, i) > kMaxVariance) {
      const double k = std::sqrt(kMaxVariance / cov(i, i));
      cov.row(i) *= k;
      cov.col(i) *= k;
    }
  if (cov.allFinite()) f.covariance = 0.5 * (cov + cov.transpose());
  return f;
}

}  // namespace sb::odometry
