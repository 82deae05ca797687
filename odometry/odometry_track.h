#pragma once
// The robot's odometry as one stream (docs/odometry.md): stamped camera poses in an
// odometry frame, whatever door they came in by (a sequence's odometry.txt, a bag's nav_msgs/Odometry with its
// /tf_static mount, the ROS bridge's ~odom_topic, the socket's ?ODOM request).
//
// Each sample is T_camera_to_odom: the camera's pose in the odometry frame (the base's odometry composed with
// the camera mount), the camera in the optical convention of groundtruth.txt (x right, y down, z forward).
// The odometry frame is the base's (ROS REP 103: x forward, y left, z up), so its z axis is "up" for a map.
// Only relative motion is used for tracking: poseAt(t1)^-1 * poseAt(t2) is the camera's motion between two
// frames. Stamps are seconds on the depth frames' clock.
//
// Thread-safe: the daemon adds samples on its event loop while the SLAM thread reads them.

#include <Eigen/Geometry>
#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>
#include <string>

#include "drivers/odometry_sample.h"
#include "odometry/odometry_config.h"

namespace sb::odometry {

struct OdometryTrackParams {
  size_t capacity = 4096;  // samples kept (oldest dropped): 80 s at 50 Hz
  // No interpolation across a gap between two samples longer than this; a stamp past the newest sample by at
  // most maxExtrapolationS is extrapolated with its velocity. The run's config (odometry.max_gap_s,
  // odometry.max_extrapolation_s) sets them for the fusion (poseAt with bounds); these are its defaults.
  double maxGapS = OdometryConfig{}.maxGapS;
  double maxExtrapolationS = OdometryConfig{}.maxExtrapolationS;
};

class OdometryTrack {
 public:
  explicit OdometryTrack(const OdometryTrackParams& params = {});
  // Copies hold the samples of the moment (the source locked while copying).
  OdometryTrack(const OdometryTrack& other);
  OdometryTrack& operator=(const OdometryTrack& other);

  // Adds a sample. Refused (false; `why` says why, naming the stamp) when its stamp is not finite or not after
  // the newest sample's, or its pose is not finite. Never throws.
  bool add(const OdometrySample& sample, std::string* why = nullptr);
  // The camera pose in the odometry frame at `t`: interpolated between the samples around it (position
  // linearly, rotation by slerp), or extrapolated with the newest two samples' motion up to maxExtrapolationS
  // past the newest. nullopt before the first sample, inside a gap longer than maxGapS, past the bound, or
  // with no sample.
  std::optional<Eigen::Isometry3d> poseAt(double t) const { return poseAt(t, params_.maxGapS, params_.maxExtrapolationS); }
  // The same with other bounds (the run's config).
  std::optional<Eigen::Isometry3d> poseAt(double t, double maxGapS, double maxExtrapolationS) const;
  // The covariance at `t` of the nearest sample that states one (nullopt: none stated).
  std::optional<Matrix6> covarianceAt(double t) const;

  size_t size() const;
  std::optional<double> newestStamp() const;
  const OdometryTrackParams& params() const { return params_; }

 private:
  OdometryTrackParams params_;
  mutable std::mutex mutex_;
  std::deque<OdometrySample> samples_;  // stamps strictly increasing
};

// Interpolation between two poses: a at s = 0, b at s = 1 (position linear, rotation slerp).
Eigen::Isometry3d interpolatePose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double s);

// Reads an odometry.txt (TUM format: `timestamp tx ty tz qx qy qz qw`, T_camera_to_odom; '#' comments) into
// a track whose capacity holds the whole file. Throws sb::Error naming the file and line on bad input.
OdometryTrack readOdometryFile(const std::string& path, OdometryTrackParams params = {});

}  // namespace sb::odometry
