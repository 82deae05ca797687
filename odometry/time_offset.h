#pragma once
// The odometry's clock against the camera's (issue 52; docs/wheel-faults.md). A base's odometry is stamped
// when its driver publishes it, not when the wheels turned: a constant latency of tens of milliseconds is usual
// and nobody measures it. Uncompensated, every change of motion reaches the fusion late: at the start and end of
// an in-place turn the wheels say "still turning" or "not yet" by a few degrees a frame, along motions the view
// fixes, and the pose is pulled off. Estimated online as visual-inertial systems estimate their camera-IMU
// offset: over the recent frames the view fixed, the offset that best matches the wheels' turn between two
// frames' stamps (shifted by it) to the view's is taken, once the frames hold a change of turn rate that tells
// offsets apart (a constant rate matches any offset). The estimate stays within a stated range of the start
// value (`odometry.time_offset_s`, `odometry.time_offset_range_s`).

#include <cstdint>
#include <deque>
#include <vector>

#include "odometry/odometry_config.h"
#include "odometry/odometry_track.h"

namespace sb::odometry {

class TimeOffset {
 public:
  explicit TimeOffset(const OdometryConfig& config);
  // Seconds to add to a frame's stamp to read the odometry at the same instant.
  double offset() const { return offset_; }
  // Whether the evidence has moved the estimate from its start value.
  bool learnt() const { return learnt_; }
  // A frame the view fixed (it constrains every rotation): the view's rotation between the frames at stamps t0
  // and t1 (its rotation vector, radians, in the earlier camera's frame).
  void add(const OdometryTrack& track, double t0, double t1, const Eigen::Vector3d& viewRotation);

  // What was learnt (a map store keeps it for the next run, runtime/kept_odometry.h): the offset, whether the
  // evidence moved it, and the frames of evidence.
  struct State {
    double offsetS = 0.0;
    bool learnt = false;
    int64_t frames = 0;
  };
  State state() const { return {offset_, learnt_, frames_}; }
  // Starts from an earlier run's learnt offset (the offset tried nearest it): from then on the evidence must
  // move it from there, as it must from the start value otherwise. False, and nothing changed, when it was not
  // learnt, when this run's offset is fixed (time_offset_range_s 0: the config's word) or when it lies outside
  // this run's range.
  bool restore(const State& kept);

 private:
  static constexpr int kEveryFrames = 15;      // the estimate is revised this often
  static constexpr int kMinFrames = 30;        // and from this many frames of evidence on
  static constexpr double kStepS = 0.005;      // the offsets tried, this far apart
  static constexpr double kMaxPendingS = 2.0;  // a frame the odometry has not covered by then is dropped
  void revise();

  OdometryConfig config_;
  double offset_;
  bool learnt_ = false;
  struct Sample {
    double t0, t1;
    Eigen::Vector3d viewRotation;
  };
  std::deque<Sample> pending_;  // frames the odometry does not cover yet over the whole range
  // The offsets tried, and for each the squared difference between the wheels' rotation and the view's summed
  // over every frame so far (radians^2): the evidence of the whole run, not of a window, since a latency is a
  // property of the driver and noise averages out only over many turns.
  std::vector<double> offsets_, cost_;
  size_t from_ = 0;  // the offset the evidence must beat: the start value's, or a restored one's
  int64_t frames_ = 0;
  int sinceRevision_ = 0;
};

}  // namespace sb::odometry
