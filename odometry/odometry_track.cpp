#include "odometry/odometry_track.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace sb::odometry {

namespace {

bool finitePose(const Eigen::Isometry3d& T) { return T.matrix().allFinite(); }

std::string stamp(double t) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", t);
  return buf;
}

std::string seconds(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

Eigen::Isometry3d interpolatePose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double s) {
  const Eigen::Quaterniond qa(a.rotation()), qb(b.rotation());
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = qa.slerp(s, qb).normalized().toRotationMatrix();
  T.translation() = (1.0 - s) * a.translation() + s * b.translation();
  return T;
}

OdometryTrack::OdometryTrack(const OdometryTrackParams& params) : params_(params) {
  if (params_.capacity < 2) params_.capacity = 2;
}

OdometryTrack::OdometryTrack(const OdometryTrackParams& params, std::unique_ptr<OdometrySampleSource> source)
    : OdometryTrack(params) {
  source_ = std::move(source);
  std::lock_guard<std::mutex> lock(mutex_);
  while (source_ && samples_.size() < params_.capacity) {  // the first window at once (size() says it)
    OdometrySample s;
    if (!source_->next(s)) source_.reset();
    else push(s);
  }
}

OdometryTrack::OdometryTrack(const OdometryTrack& other) {
  std::lock_guard<std::mutex> lock(other.mutex_);
  params_ = other.params_;
  samples_ = other.samples_;
  added_ = other.added_;
  candidates_ = other.candidates_;
  frameStamp_ = other.frameStamp_;
}

OdometryTrack& OdometryTrack::operator=(const OdometryTrack& other) {
  if (this == &other) return *this;
  std::scoped_lock lock(mutex_, other.mutex_);
  params_ = other.params_;
  samples_ = other.samples_;
  added_ = other.added_;
  candidates_ = other.candidates_;
  frameStamp_ = other.frameStamp_;
  source_.reset();
  return *this;
}

OdometryTrack::OdometryTrack(OdometryTrack&& other) noexcept {
  std::lock_guard<std::mutex> lock(other.mutex_);
  params_ = other.params_;
  samples_ = std::move(other.samples_);
  added_ = other.added_;
  candidates_ = std::move(other.candidates_);
  frameStamp_ = other.frameStamp_;
  source_ = std::move(other.source_);
}

OdometryTrack::~OdometryTrack() = default;

void OdometryTrack::push(const OdometrySample& sample) const {
  samples_.push_back(sample);
  ++added_;
  while (samples_.size() > params_.capacity) samples_.pop_front();
}

void OdometryTrack::feedTo(double t) const {
  // Read until a sample at or past t is held (interpolation needs the one after t), or the source ends.
  while (source_ && std::isfinite(t) && (samples_.empty() || samples_.back().timestamp < t)) {
    OdometrySample s;
    if (!source_->next(s)) source_.reset();
    else push(s);
  }
}

void OdometryTrack::noteFrameStamp(double t) {
  if (!std::isfinite(t)) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (!frameStamp_ || t > *frameStamp_) frameStamp_ = t;
}

bool OdometryTrack::add(const OdometrySample& sample, std::string* why) {
  const auto refuse = [&](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (!std::isfinite(sample.timestamp)) return refuse("odometry sample with a stamp that is not a finite number");
  if (!finitePose(sample.T_camera_to_odom))
    return refuse("odometry sample at " + stamp(sample.timestamp) + " s with a pose that is not finite");
  if (sample.covariance && !sample.covariance->allFinite())
    return refuse("odometry sample at " + stamp(sample.timestamp) + " s with a covariance that is not finite");
  std::lock_guard<std::mutex> lock(mutex_);
  const double t = sample.timestamp, leap = params_.maxLeapS;
  const std::optional<double> newest = samples_.empty() ? std::nullopt : std::optional<double>(samples_.back().timestamp);
  if (newest && t <= *newest) {
    // A duplicate or a sample out of order: refused. Far before the newest (and not before the frames' clock):
    // perhaps the source's clock went back, or the newest was absurd; held until samples confirm it.
    const bool farBack = *newest - t > leap && (!frameStamp_ || t >= *frameStamp_ - leap);
    if (!farBack)
      return refuse("odometry sample at " + stamp(t) + " s is not after the newest (" + stamp(*newest) +
                    " s): stamps must increase");
    return hold(sample, stamp(*newest - t) + " s before the newest sample (" + stamp(*newest) + " s)", why);
  }
  std::optional<double> reference = newest;
  if (frameStamp_ && (!reference || *frameStamp_ > *reference)) reference = frameStamp_;
  if (!reference || t - *reference <= leap) {
    push(sample);
    candidates_.clear();  // the clock in use goes on: held samples of another one stay refused
    return true;
  }
  const bool byFrame = frameStamp_ && *reference == *frameStamp_;
  return hold(sample,
              stamp(t - *reference) + " s past the newest " + (byFrame ? "frame" : "sample") + " (" + stamp(*reference) +
                  " s)",
              why);
}

bool OdometryTrack::hold(const OdometrySample& sample, const std::string& where, std::string* why) {
  const double t = sample.timestamp;
  if (!candidates_.empty() && t > candidates_.back().timestamp && t - candidates_.back().timestamp <= params_.maxLeapS)
    candidates_.push_back(sample);
  else
    candidates_.assign(1, sample);
  if (candidates_.size() >= kOdometryClockConfirmSamples) {  // the new clock is confirmed: take it
    const double first = candidates_.front().timestamp;
    while (!samples_.empty() && samples_.back().timestamp >= first) samples_.pop_back();
    for (const OdometrySample& s : candidates_) push(s);
    candidates_.clear();
    return true;
  }
  if (why)
    *why = "odometry sample at " + stamp(t) + " s is " + where + ": more than the " + seconds(params_.maxLeapS) +
           " s a stamp may leap (kMaxOdometryLeapS); refused, held until " +
           std::to_string(kOdometryClockConfirmSamples - candidates_.size()) +
           " more samples in a row confirm its clock";
  return false;
}

std::optional<Eigen::Isometry3d> OdometryTrack::poseAt(double t, double maxGapS, double maxExtrapolationS) const {
  std::lock_guard<std::mutex> lock(mutex_);
  feedTo(t);
  if (samples_.empty() || !std::isfinite(t) || t < samples_.front().timestamp) return std::nullopt;
  const OdometrySample& newest = samples_.back();
  if (t >= newest.timestamp) {
    if (t - newest.timestamp > maxExtrapolationS) return std::nullopt;
    if (t == newest.timestamp || samples_.size() < 2) return newest.T_camera_to_odom;
    const OdometrySample& before = samples_[samples_.size() - 2];
    const double span = newest.timestamp - before.timestamp;
    if (span > maxGapS) return std::nullopt;
    // Constant velocity past the newest: s > 1 on the segment before it.
    return interpolatePose(before.T_camera_to_odom, newest.T_camera_to_odom, 1.0 + (t - newest.timestamp) / span);
  }
  const auto after = std::upper_bound(samples_.begin(), samples_.end(), t,
                                      [](double v, const OdometrySample& s) { return v < s.timestamp; });
  const OdometrySample& b = *after;
  const OdometrySample& a = *(after - 1);
  const double span = b.timestamp - a.timestamp;
  if (span > maxGapS) return std::nullopt;
  return interpolatePose(a.T_camera_to_odom, b.T_camera_to_odom, (t - a.timestamp) / span);
}

std::optional<Matrix6> OdometryTrack::covarianceAt(double t) const {
  std::lock_guard<std::mutex> lock(mutex_);
  feedTo(t);
  std::optional<Matrix6> best;
  double bestDt = INFINITY;
  for (const auto& s : samples_)
    if (s.covariance && std::abs(s.timestamp - t) < bestDt) {
      bestDt = std::abs(s.timestamp - t);
      best = s.covariance;
    }
  return best;
}

size_t OdometryTrack::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return samples_.size();
}

std::optional<double> OdometryTrack::newestStamp() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (samples_.empty()) return std::nullopt;
  return samples_.back().timestamp;
}

std::optional<double> OdometryTrack::oldestStamp() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (samples_.empty()) return std::nullopt;
  return samples_.front().timestamp;
}

uint64_t OdometryTrack::added() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return added_;
}

}  // namespace sb::odometry
