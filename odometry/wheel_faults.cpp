#include "odometry/wheel_faults.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace sb::odometry {

const char* wheelFaultName(WheelFault fault) {
  switch (fault) {
    case WheelFault::disputed: return "disputed";
    case WheelFault::slipping: return "slipping";
    case WheelFault::kidnapped: return "kidnapped";
    case WheelFault::none: break;
  }
  return "none";
}

namespace {

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

void MapAgreement::add(double pairAgreement) {
  recent_.push_back(pairAgreement);
  if (recent_.size() > kFrames) recent_.pop_front();
}

double MapAgreement::floor() const {
  if (recent_.empty()) return 0.0;
  return fraction_ * median(std::vector<double>(recent_.begin(), recent_.end()));
}

bool MapAgreement::holds(double pairAgreement) const { return recent_.empty() || pairAgreement >= floor(); }

void MapAgreement::addCoverage(double coverage) {
  coverage_.push_back(coverage);
  if (coverage_.size() > kFrames) coverage_.pop_front();
}

bool MapAgreement::covered(double coverage) const {
  return coverage_.empty() ||
         coverage >= kCoveredFraction * median(std::vector<double>(coverage_.begin(), coverage_.end()));
}

bool MapAgreement::contradicted(double pairAgreement, double coverage) const {
  if (coverage <= 0.0 || holds(pairAgreement)) return false;  // a view paired with nothing contradicts nothing
  if (coverage_.empty()) return true;  // covered, as covered() says without history
  const double usual = median(std::vector<double>(coverage_.begin(), coverage_.end()));
  return coverage >= kCoveredFraction * usual || coverage * (1.0 - pairAgreement) >= kContradictedFraction * usual;
}

std::string TurnCorrections::add(double stamp, const Eigen::Vector3d& rotation, double sigmaRad, double sigmas,
                                 double floorRad) {
  frames_.push_back(Frame{stamp, rotation, sigmaRad * sigmaRad});
  while (frames_.front().stamp < stamp - windowS_) frames_.pop_front();
  if (frames_.size() < kMinFrames) return {};
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double variance = 0.0;
  for (const Frame& f : frames_) {
    sum += f.rotation;
    variance += f.variance;
  }
  const double n = static_cast<double>(frames_.size());
  const double gate = std::max(sigmas * std::sqrt(variance), floorRad * std::sqrt(n));
  const Eigen::Vector3d mean = sum / n;
  if (sum.norm() <= gate || rotation.dot(mean) < 0.5 * mean.squaredNorm()) return {};
  char buf[160];
  std::snprintf(buf, sizeof buf, "the view turned the wheels' prediction by %.2f deg over the last %.2f s",
                sum.norm() * 180.0 / M_PI, stamp - frames_.front().stamp);
  return buf;
}

void FaultWatch::begin(double stamp) {
  if (fault_ != WheelFault::none) return;
  fault_ = WheelFault::disputed;
  since_ = lastEvidence_ = stamp;
  wheelsAgainst_ = viewAgainst_ = 0;
}

bool FaultWatch::diverging(double stamp, double correctionM, bool withinReach) {
  calm_ = 0;
  begin(stamp);
  if (why_.empty()) why_ = "the wheels and the view disagree: undecided";
  if (rising_ > 0 && correctionM > lastCorrectionM_) {
    ++rising_;
  } else {
    rising_ = withinReach ? 1 : 0;
    firstCorrectionM_ = correctionM;
  }
  lastCorrectionM_ = correctionM;
  return rising_ >= kMinFrames && correctionM >= kGrowth * firstCorrectionM_;
}

bool FaultWatch::steady(double stamp, const Eigen::Isometry3d& correction, double toleranceM, bool withinReach) {
  calm_ = 0;
  begin(stamp);
  if (why_.empty()) why_ = "the wheels and the view disagree: undecided";
  const bool same =
      steady_ && (correction.translation() - steady_->translation()).norm() <= toleranceM &&
      Eigen::AngleAxisd(steady_->linear().transpose() * correction.linear()).angle() <= kSteadyDeg * M_PI / 180.0;
  if (same) {
    ++steadyFrames_;
  } else if (withinReach) {
    steadyFrames_ = 1;
    steadySince_ = stamp;
  } else {
    steadyFrames_ = 0;
  }
  if (steadyFrames_ == 1)
    steady_ = correction;
  else if (steadyFrames_ == 0)
    steady_.reset();
  return steadyFrames_ >= kMinFrames && stamp - steadySince_ >= decideS_;
}

void FaultWatch::wheelsContradicted(double stamp) {
  calm_ = 0;
  rising_ = 0;
  steady_.reset();
  if (fault_ == WheelFault::slipping || fault_ == WheelFault::kidnapped) return;
  begin(stamp);
  ++wheelsAgainst_;
  lastEvidence_ = stamp;
  why_ = "the view holds the map while the wheels report another motion";
  if (wheelsAgainst_ >= kMinFrames && stamp - since_ >= decideS_ && wheelsAgainst_ > viewAgainst_) {
    fault_ = WheelFault::slipping;
    why_ = "the wheels' motion is contradicted by a view that holds the map: not used until they agree again";
  }
}

void FaultWatch::viewContradicted(double stamp) {
  calm_ = 0;
  rising_ = 0;
  steady_.reset();
  if (fault_ == WheelFault::kidnapped) return;
  if (fault_ == WheelFault::slipping) fault_ = WheelFault::none;  // neither side is trusted now: decide again
  begin(stamp);
  ++viewAgainst_;
  lastEvidence_ = stamp;
  why_ = "the view does not fit the map near the wheels' pose";
  if (viewAgainst_ >= kMinFrames && stamp - since_ >= decideS_ && viewAgainst_ > wheelsAgainst_) {
    fault_ = WheelFault::kidnapped;
    why_ = "the view has not fitted the map near the wheels' pose for the decision time: the robot is elsewhere";
  }
}

bool FaultWatch::concludeKidnapped() {
  if (fault_ != WheelFault::disputed || viewAgainst_ < kMinFrames || viewAgainst_ <= wheelsAgainst_) return false;
  fault_ = WheelFault::kidnapped;
  why_ = "the view has not fitted the map near the wheels' pose while they carried it: the robot is elsewhere";
  return true;
}

void FaultWatch::agreed(double stamp) {
  rising_ = 0;
  steady_.reset();
  if (fault_ == WheelFault::none) return;
  if (calm_ == 0) calmSince_ = stamp;
  ++calm_;
  if (calm_ >= kMinFrames && stamp - calmSince_ >= (fault_ == WheelFault::disputed ? 0.0 : calmS_)) reset();
}

void FaultWatch::expire(double stamp) {
  if (fault_ == WheelFault::disputed && stamp - lastEvidence_ > kStaleDecisions * decideS_) reset();
}

void FaultWatch::reset() {
  fault_ = WheelFault::none;
  wheelsAgainst_ = viewAgainst_ = calm_ = rising_ = 0;
  steady_.reset();
  why_.clear();
}

}  // namespace sb::odometry
