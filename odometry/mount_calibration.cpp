#include "odometry/mount_calibration.h"

#include <algorithm>
#include <cmath>

namespace sb::odometry {

namespace {
constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
}

void MountCalibration::learn(const Eigen::Matrix3d& viewStep, const OdometryStep& raw) {
  const Eigen::AngleAxisd view(viewStep), wheels(raw.delta.linear());
  if (view.angle() < kMinStepDeg * kDegToRad || wheels.angle() < kMinStepDeg * kDegToRad) return;
  if (view.axis().dot(wheels.axis()) < std::cos(kMaxAxisDeg * kDegToRad)) return;
  // Turns either way: both axes into the hemisphere of the odometry's up.
  const double sign = wheels.axis().dot(raw.up) < 0.0 ? -1.0 : 1.0;
  const double w = view.angle();
  viewSum_ += sign * w * view.axis();
  wheelSum_ += sign * w * wheels.axis();
  const Eigen::Vector3d diff = sign * (view.axis() - wheels.axis());
  diffSum_ += w * diff;
  diffSquares_ += w * diff.squaredNorm();
  weights_ += w;
  weightSquares_ += w * w;
  turnRad_ += w;
  if (turnRad_ < kMinTurnDeg * kDegToRad || fromFloor_) return;
  const Eigen::Vector3d mean = diffSum_ / weights_;
  const double scatter = std::max(0.0, diffSquares_ / weights_ - mean.squaredNorm());
  const double samples = weights_ * weights_ / weightSquares_;
  const double standardError = std::sqrt(scatter / samples);
  standardError_ = standardError;
  correction_ = mean.norm() >= kSignificance * standardError
                    ? Eigen::Quaterniond::FromTwoVectors(wheelSum_.normalized(), viewSum_.normalized()).toRotationMatrix()
                    : Eigen::Matrix3d::Identity();
}

void MountCalibration::floorSeen(const Eigen::Vector3d& floorUp, const Eigen::Vector3d& assumedUp) {
  if (!wantsFloor() || !(floorUp.norm() > 0.0) || !(assumedUp.norm() > 0.0)) return;
  floorUps_.push_back(floorUp.normalized());
  floorFrames_ = floorUps_.size();
  if (floorFrames_ < kMinFloorFrames) return;
  Eigen::Vector3d median;
  std::vector<double> values(floorFrames_);
  for (int axis = 0; axis < 3; ++axis) {
    for (size_t i = 0; i < floorFrames_; ++i) values[i] = floorUps_[i][axis];
    std::nth_element(values.begin(), values.begin() + floorFrames_ / 2, values.end());
    median[axis] = values[floorFrames_ / 2];
  }
  median.normalize();
  for (size_t i = 0; i < floorFrames_; ++i) values[i] = std::acos(std::clamp(floorUps_[i].dot(median), -1.0, 1.0));
  std::nth_element(values.begin(), values.begin() + floorFrames_ / 2, values.end());
  floorSpreadRad_ = values[floorFrames_ / 2];
  if (floorSpreadRad_ > kFloorAgreeDeg * kDegToRad) return;  // no one floor: the turns decide
  correction_ = Eigen::Quaterniond::FromTwoVectors(assumedUp.normalized(), median).toRotationMatrix();
  fromFloor_ = true;
}

const char* MountCalibration::source() const {
  if (fromFloor_) return "floor";
  return errorDeg() > 0.0 ? "turns" : "";
}

OdometryStep MountCalibration::correct(const OdometryStep& raw) const {
  OdometryStep out = raw;
  Eigen::Isometry3d E = Eigen::Isometry3d::Identity();
  E.linear() = correction_;
  out.delta = E * raw.delta * E.inverse();
  out.up = correction_ * raw.up;
  return out;
}

double MountCalibration::sigmaDeg(double priorDeg) const {
  if (fromFloor_)  // the frames' floors spread about their median: its error, as if the frames were independent
    return std::min(priorDeg, kSignificance * floorSpreadRad_ / std::sqrt(static_cast<double>(floorFrames_)) / kDegToRad);
  if (turnRad_ < kMinTurnDeg * kDegToRad) return priorDeg;
  return std::min(priorDeg, kSignificance * standardError_ / kDegToRad);
}

void MountCalibration::restore(const State& s) {
  viewSum_ = s.viewSum, wheelSum_ = s.wheelSum, diffSum_ = s.diffSum;
  diffSquares_ = s.diffSquares, weights_ = s.weights, weightSquares_ = s.weightSquares;
  turnRad_ = s.turnRad, standardError_ = s.standardError, correction_ = s.correction;
  // The floor's frames are not kept, only their count: a mount learnt from 300 floors stands; one learnt from fewer
  // is learnt again from this run's floors (the frames already read are gone).
  floorUps_.clear();
  floorFrames_ = s.fromFloor ? static_cast<size_t>(s.floorFrames) : 0;
  if (floorFrames_ < kEnoughFloorFrames) floorFrames_ = 0;
  floorSpreadRad_ = s.floorSpreadRad;
  fromFloor_ = s.fromFloor;
}

double MountCalibration::errorDeg() const { return Eigen::AngleAxisd(correction_).angle() / kDegToRad; }

}  // namespace sb::odometry
