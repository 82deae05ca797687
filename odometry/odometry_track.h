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
//
// Which stamps a live door may add (issue 53): a stamp may leap at most kMaxOdometryLeapS past the newest
// sample and the newest frame (noteFrameStamp), whichever is later. A sample that cannot be placed (further
// ahead, or further back than that before the newest) is refused alone, with a message naming its stamp, and
// held: when kOdometryClockConfirmSamples such samples in a row agree on a new clock (each after the last,
// within the leap), the source's clock has really moved (a robot restarted, a bag replayed again) and they
// are taken, the samples after the new clock's first dropped. So one absurd stamp (9.9e9 s) is refused and
// the next sane sample is taken; the old clock's samples, not the absurd one, stay the newest.

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "drivers/odometry_sample.h"
#include "odometry/odometry_config.h"

namespace sb::odometry {

// The most a live sample's stamp may lie past the newest sample and the newest frame (seconds), or before the
// newest sample without being a plain duplicate or reordering; beyond it a sample is held (see above).
inline constexpr double kMaxOdometryLeapS = 10.0;
// Samples in a row that must agree on a new clock before it is taken.
inline constexpr size_t kOdometryClockConfirmSamples = 3;

// Where a track's samples come from beyond add(): a file read as the frames need it (odometry_file.h).
// next() gives the samples in increasing stamp order; false at the end. It may throw sb::Error (a file that
// changed under the run).
class OdometrySampleSource {
 public:
  virtual ~OdometrySampleSource() = default;
  virtual bool next(OdometrySample& sample) = 0;
};

struct OdometryTrackParams {
  size_t capacity = 4096;  // samples kept (oldest dropped): 80 s at 50 Hz
  // The leap rule above; infinity: none (the samples of a recorded file, checked as a whole).
  double maxLeapS = kMaxOdometryLeapS;
  // No interpolation across a gap between two samples longer than this; a stamp past the newest sample by at
  // most maxExtrapolationS is extrapolated with its velocity. The run's config (odometry.max_gap_s,
  // odometry.max_extrapolation_s) sets them for the fusion (poseAt with bounds); these are its defaults.
  double maxGapS = OdometryConfig{}.maxGapS;
  double maxExtrapolationS = OdometryConfig{}.maxExtrapolationS;
};

class OdometryTrack {
 public:
  explicit OdometryTrack(const OdometryTrackParams& params = {});
  // A track fed from `source` as poseAt and covarianceAt ask for later stamps: it holds at most
  // params.capacity samples, whatever the source's length (the first ones read at once).
  OdometryTrack(const OdometryTrackParams& params, std::unique_ptr<OdometrySampleSource> source);
  // Copies hold the samples of the moment (the source locked while copying), not the sample source.
  OdometryTrack(const OdometryTrack& other);
  OdometryTrack& operator=(const OdometryTrack& other);
  OdometryTrack(OdometryTrack&& other) noexcept;  // takes the sample source along
  ~OdometryTrack();

  // Adds a sample. Refused (false; `why` says why, naming the stamp) when its stamp is not finite, not after
  // the newest sample's, or cannot be placed on the clock (the leap rule above; such a sample is held and
  // taken once samples after it confirm its clock, this call or a later one then returning true), or its
  // pose is not finite. Never throws.
  bool add(const OdometrySample& sample, std::string* why = nullptr);
  // The newest frame's stamp (the daemon's, as each frame is reported): the leap rule's other reference.
  void noteFrameStamp(double t);
  // The camera pose in the odometry frame at `t`: interpolated between the samples around it (position
  // linearly, rotation by slerp), or extrapolated with the newest two samples' motion up to maxExtrapolationS
  // past the newest. nullopt before the first sample, inside a gap longer than maxGapS, past the bound, or
  // with no sample.
  std::optional<Eigen::Isometry3d> poseAt(double t) const { return poseAt(t, params_.maxGapS, params_.maxExtrapolationS); }
  // The same with other bounds (the run's config).
  std::optional<Eigen::Isometry3d> poseAt(double t, double maxGapS, double maxExtrapolationS) const;
  // The covariance at `t` of the nearest sample that states one (nullopt: none stated).
  std::optional<Matrix6> covarianceAt(double t) const;

  size_t size() const;  // samples held
  std::optional<double> newestStamp() const;
  std::optional<double> oldestStamp() const;
  uint64_t added() const;  // samples taken since the start (held ones once confirmed), whether still held or not
  const OdometryTrackParams& params() const { return params_; }

 private:
  bool hold(const OdometrySample& sample, const std::string& where, std::string* why);  // locked
  void push(const OdometrySample& sample) const;                                          // locked
  void feedTo(double t) const;                                                            // locked

  OdometryTrackParams params_;
  mutable std::mutex mutex_;
  mutable std::deque<OdometrySample> samples_;  // stamps strictly increasing
  mutable uint64_t added_ = 0;
  std::vector<OdometrySample> candidates_;  // held samples agreeing on a clock that cannot be placed yet
  std::optional<double> frameStamp_;
  mutable std::unique_ptr<OdometrySampleSource> source_;  // nullptr: none, or read to its end
};

// Interpolation between two poses: a at s = 0, b at s = 1 (position linear, rotation slerp).
Eigen::Isometry3d interpolatePose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double s);

// Reads an odometry.txt (TUM format: `timestamp tx ty tz qx qy qz qw`, T_camera_to_odom; '#' comments) into
// a track fed from the file as the frames need it (odometry/odometry_file.h): the whole file is checked first
// (sb::Error naming the file and line on bad input), then at most kOdometryFileWindow samples are held, the
// first ones at once: memory does not grow with the file's length.
OdometryTrack readOdometryFile(const std::string& path, OdometryTrackParams params = {});

}  // namespace sb::odometry
