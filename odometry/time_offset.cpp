#include "odometry/time_offset.h"

#include <algorithm>
#include <cmath>

namespace sb::odometry {

namespace {

Eigen::Vector3d rotationVector(const Eigen::Matrix3d& r) {
  const Eigen::AngleAxisd aa(r);
  return aa.axis() * aa.angle();
}

// The evidence an offset needs over the start value: its fit of every frame so far better by this many times
// the frames' own residual variance (a likelihood ratio of 5 sigma). The residual is the view's and the wheels'
// noise together, measured, so a noisy base needs more turns to be believed, a clean one fewer.
constexpr double kEvidence = 25.0;
constexpr double kMinSigmaRad = 1e-4;  // no view knows a frame's rotation better than a tenth of a milliradian

}  // namespace

TimeOffset::TimeOffset(const OdometryConfig& config) : config_(config), offset_(config.timeOffsetS) {
  const int steps = static_cast<int>(std::floor(config_.timeOffsetRangeS / kStepS + 1e-9));
  for (int i = -steps; i <= steps; ++i) offsets_.push_back(config_.timeOffsetS + i * kStepS);
  cost_.assign(offsets_.size(), 0.0);
  from_ = offsets_.size() / 2;
}

bool TimeOffset::restore(const State& kept) {
  if (!kept.learnt || !std::isfinite(kept.offsetS) || config_.timeOffsetRangeS <= 0.0) return false;
  if (std::abs(kept.offsetS - config_.timeOffsetS) > config_.timeOffsetRangeS + 0.5 * kStepS) return false;
  size_t nearest = 0;
  for (size_t i = 1; i < offsets_.size(); ++i)
    if (std::abs(offsets_[i] - kept.offsetS) < std::abs(offsets_[nearest] - kept.offsetS)) nearest = i;
  from_ = nearest;
  offset_ = offsets_[nearest];
  learnt_ = true;
  return true;
}

void TimeOffset::add(const OdometryTrack& track, double t0, double t1, const Eigen::Vector3d& viewRotation) {
  if (config_.timeOffsetRangeS <= 0.0 || !(t1 > t0) || !viewRotation.allFinite()) return;
  pending_.push_back({t0, t1, viewRotation});
  // A frame counts once the odometry covers it at both ends of the range (the newest samples may lag).
  const double lo = offsets_.front(), hi = offsets_.back();
  while (!pending_.empty()) {
    const Sample& s = pending_.front();
    const bool old = t1 - s.t1 > kMaxPendingS;
    if (!track.poseAt(s.t0 + lo, config_.maxGapS, config_.maxExtrapolationS) ||
        !track.poseAt(s.t1 + hi, config_.maxGapS, config_.maxExtrapolationS)) {
      if (!old) break;
      pending_.pop_front();  // never covered (a gap in the odometry): no evidence
      continue;
    }
    for (size_t i = 0; i < offsets_.size(); ++i) {
      const auto a = track.poseAt(s.t0 + offsets_[i], config_.maxGapS, config_.maxExtrapolationS);
      const auto b = track.poseAt(s.t1 + offsets_[i], config_.maxGapS, config_.maxExtrapolationS);
      if (a && b) cost_[i] += (rotationVector(a->linear().transpose() * b->linear()) - s.viewRotation).squaredNorm();
    }
    ++frames_;
    pending_.pop_front();
  }
  if (++sinceRevision_ >= kEveryFrames) {
    sinceRevision_ = 0;
    revise();
  }
}

void TimeOffset::revise() {
  if (frames_ < kMinFrames) return;
  const size_t best = static_cast<size_t>(std::min_element(cost_.begin(), cost_.end()) - cost_.begin());
  // Only evidence moves it: frames at a constant turn rate (or none) match every offset alike, and noise alone
  // lowers some offset's cost a little.
  const double variance = std::max(cost_[best] / static_cast<double>(frames_), kMinSigmaRad * kMinSigmaRad);
  if (cost_[from_] - cost_[best] <= kEvidence * variance) return;
  offset_ = offsets_[best];
  learnt_ = true;
}

}  // namespace sb::odometry
