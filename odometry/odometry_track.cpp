#include "odometry/odometry_track.h"

#include <algorithm>
#include <cmath>

#include "core/trajectory.h"

namespace sb::odometry {

namespace {

bool finitePose(const Eigen::Isometry3d& T) { return T.matrix().allFinite(); }

std::string stamp(double t) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", t);
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

OdometryTrack::OdometryTrack(const OdometryTrack& other) {
  std::lock_guard<std::mutex> lock(other.mutex_);
  params_ = other.params_;
  samples_ = other.samples_;
}

OdometryTrack& OdometryTrack::operator=(const OdometryTrack& other) {
  if (this == &other) return *this;
  std::scoped_lock lock(mutex_, other.mutex_);
  params_ = other.params_;
  samples_ = other.samples_;
  return *this;
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
  if (!samples_.empty() && sample.timestamp <= samples_.back().timestamp)
    return refuse("odometry sample at " + stamp(sample.timestamp) + " s is not after the newest (" +
                  stamp(samples_.back().timestamp) + " s): stamps must increase");
  samples_.push_back(sample);
  while (samples_.size() > params_.capacity) samples_.pop_front();
  return true;
}

std::optional<Eigen::Isometry3d> OdometryTrack::poseAt(double t, double maxGapS, double maxExtrapolationS) const {
  std::lock_guard<std::mutex> lock(mutex_);
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

OdometryTrack readOdometryFile(const std::string& path, OdometryTrackParams params) {
  const Trajectory poses = readTumTrajectory(path);  // names the file and line on bad input
  params.capacity = std::max(params.capacity, poses.size());
  OdometryTrack track(params);
  for (const TimedPose& p : poses) track.add(OdometrySample{p.timestamp, p.T_camera_to_world, std::nullopt});
  return track;
}

}  // namespace sb::odometry
