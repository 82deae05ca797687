#include "odometry/odometry_calibration.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "pipeline/icp_solve.h"

namespace sb::odometry {

namespace {

constexpr double kPi = 3.14159265358979323846;
// The prior: a base's odometry is within a few percent and its yaw drift within a degree per second (an
// uncalibrated MEMS gyro); the estimate never leaves three of these sigmas (beyond, the base is broken, and
// the slip test, not the calibration, must deal with it).
constexpr double kScalePrior = 0.05;
constexpr double kYawScalePrior = 0.05;
constexpr double kYawBiasPrior = 1.0 * kPi / 180.0;  // rad/s
constexpr double kBound = 3.0;                       // prior sigmas
// Evidence fades over this time as well as over the configured distance (a gyro's bias follows its temperature).
constexpr double kWindowS = 600.0;
// An observation this many sigmas off the current estimate is not calibration (a slip, a stuck track): skipped.
constexpr double kGateSigmas = 5.0;
// ICP's rotation error: its translation error over a 1 m lever (the scene's depth is metres).
constexpr double kLeverM = 1.0;

// The rotation of R about the unit axis `up` (radians, right-handed).
double turnAbout(const Eigen::Matrix3d& R, const Eigen::Vector3d& up) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis().dot(up);
}

// The world-frame twist that moves `pose` by `local` (a small motion in the camera's frame).
Twist twistOfLocal(const Eigen::Isometry3d& pose, const Eigen::Isometry3d& local) {
  return transformToTwist(pose * local * pose.inverse());
}

}  // namespace

OdometryCalibration::OdometryCalibration(const OdometryConfig& config)
    : config_(config), scaleInfo_(1.0 / (kScalePrior * kScalePrior)) {
  yawInfo_ << 1.0 / (kYawScalePrior * kYawScalePrior), 0.0, 0.0, 1.0 / (kYawBiasPrior * kYawBiasPrior);
}

void OdometryCalibration::restore(const CalibrationState& s) {
  scaleInfo_ = s.scaleInfo;
  scaleVec_ = s.scaleVec;
  yawInfo_ = s.yawInfo;
  yawVec_ = s.yawVec;
  frames_ = s.frames;
}

OdometryCalibration::Excess OdometryCalibration::excess() const {
  Excess x;
  x.scale = std::clamp(scaleVec_ / scaleInfo_, -kBound * kScalePrior, kBound * kScalePrior);
  const Eigen::Vector2d yaw = yawInfo_.inverse() * yawVec_;
  x.yawScale = std::clamp(yaw(0), -kBound * kYawScalePrior, kBound * kYawScalePrior);
  x.yawBiasRadPerS = std::clamp(yaw(1), -kBound * kYawBiasPrior, kBound * kYawBiasPrior);
  return x;
}

CalibrationEstimate OdometryCalibration::estimate() const {
  // The truth is the reading times (1 - excess): the reading is (1 + e) times the truth with e = x / (1 - x).
  const Excess x = excess();
  CalibrationEstimate e;
  e.scale = x.scale / (1.0 - x.scale);
  e.yawScale = x.yawScale / (1.0 - x.yawScale);
  e.yawBiasRadPerS = x.yawBiasRadPerS / (1.0 - x.yawScale);
  e.scaleSigma = 1.0 / std::sqrt(scaleInfo_);
  const Eigen::Matrix2d cov = yawInfo_.inverse();
  e.yawScaleSigma = std::sqrt(cov(0, 0));
  e.yawBiasSigmaRadPerS = std::sqrt(cov(1, 1));
  e.frames = frames_;
  return e;
}

OdometryStep OdometryCalibration::correct(const OdometryStep& raw) const {
  if (!enabled() || frames_ == 0) return raw;
  const Excess x = excess();
  OdometryStep out = raw;
  out.delta.translation() = raw.delta.translation() * (1.0 - x.scale);
  const double measured = turnAbout(raw.delta.linear(), raw.up);
  const double turn = measured * (1.0 - x.yawScale) - x.yawBiasRadPerS * raw.dt;
  out.delta.linear() = Eigen::AngleAxisd(turn - measured, raw.up).toRotationMatrix() * raw.delta.linear();
  return out;
}

void OdometryCalibration::learn(const TrackingQuality& q, const Eigen::Isometry3d& previous,
                                const Eigen::Isometry3d& tracked, const OdometryStep& raw) {
  if (!enabled() || !q.known || q.structure.isZero() || !(raw.dt > 0)) return;
  // Old evidence fades towards the prior.
  const double keep = std::exp(-(raw.distanceM() / config_.calibrationWindowM + raw.dt / kWindowS));
  const double scalePrior = 1.0 / (kScalePrior * kScalePrior);
  scaleInfo_ = scalePrior + keep * (scaleInfo_ - scalePrior);
  scaleVec_ *= keep;
  Eigen::Matrix2d yawPrior = Eigen::Matrix2d::Zero();
  yawPrior.diagonal() << 1.0 / (kYawScalePrior * kYawScalePrior), 1.0 / (kYawBiasPrior * kYawBiasPrior);
  yawInfo_ = yawPrior + keep * (yawInfo_ - yawPrior);
  yawVec_ *= keep;

  const Excess now = excess();
  const Eigen::Isometry3d seen = previous.inverse() * tracked;  // ICP's step, in the earlier camera's frame
  const double cFull = config_.fullConditioning;
  bool used = false;
  // The distance: along the wheels' direction of travel, where the view fixes that motion.
  const double odoM = raw.distanceM();
  if (odoM > config_.noiseFloorM) {
    const Eigen::Vector3d dir = raw.delta.translation() / odoM;
    Eigen::Isometry3d nudge = Eigen::Isometry3d::Identity();
    nudge.translation() = dir * 1e-3;
    const double c = conditioningAlong(q, twistOfLocal(previous, nudge) / 1e-3);
    const double icpM = seen.translation().dot(dir);
    const double var = config_.icpSigmaM * config_.icpSigmaM * cFull / std::max(c, 1e-12) + raw.sigmaM * raw.sigmaM;
    // Regressed on the wheels' reading, whose noise is small, not on ICP's: with ICP's noise on both sides the
    // slope would be pulled towards -1 (errors in variables), most where the motion is small.
    const double residual = odoM - icpM - now.scale * odoM;
    const bool plausible = std::abs(odoM - icpM) <= kBound * kScalePrior * odoM;
    if (c >= config_.minConditioning && plausible && std::abs(residual) <= kGateSigmas * std::sqrt(var)) {
      scaleInfo_ += odoM * odoM / var;
      scaleVec_ += odoM * (odoM - icpM) / var;
      used = true;
    }
  }
  // The turn about the odometry's up axis (through the camera centre), where the view fixes that rotation.
  const Eigen::Isometry3d turnNudge(Eigen::AngleAxisd(1e-3, raw.up));
  const double c = conditioningAlong(q, twistOfLocal(previous, turnNudge) / 1e-3);
  const double icpRad = turnAbout(seen.linear(), raw.up);
  const double odoRad = turnAbout(raw.delta.linear(), raw.up);
  const double icpSigmaRad = config_.icpSigmaM / kLeverM;
  const double var = icpSigmaRad * icpSigmaRad * cFull / std::max(c, 1e-12) + raw.sigmaRad * raw.sigmaRad;
  const Eigen::Vector2d x(odoRad, raw.dt);  // the wheels' reading, as for the distance
  const double residual = odoRad - icpRad - x.dot(Eigen::Vector2d(now.yawScale, now.yawBiasRadPerS));
  if (c >= config_.minConditioning && std::abs(residual) <= kGateSigmas * std::sqrt(var)) {
    yawInfo_ += x * x.transpose() / var;
    yawVec_ += x * (odoRad - icpRad) / var;
    used = true;
  }
  if (used) ++frames_;
}

}  // namespace sb::odometry
