#pragma once
// Tracking state and recovery for every controller (issue 29; tracking_state.h). The runner calls it on each
// frame:
//   trackFrame -> [recovering: the plain track is discarded] -> controller -> resolve() -> finishFrame -> after()
// Failed tracks in a row up to lost_after_failed_frames keep the controller's handling (its bounded
// extrapolation); from then on plain tracking is not trusted (a track from a stale pose after a kidnap can pass
// the residual and inlier tests in the wrong place): the pose is held, nothing is fused, and each frame the
// relocaliser (reloc/relocaliser.h) tries candidate poses until one is confirmed over consecutive frames.
// While tracking is good the frames feed the relocaliser's keyframes.
// With the robot's odometry (docs/odometry.md) a tracked pose is fused with the odometry's prediction, a frame
// depth cannot track follows the odometry (state odometry) for a bounded distance and time, and the relocaliser
// starts from the odometry's pose and refuses a candidate the odometry contradicts. With or without it, a
// tracked motion the platform cannot make is not trusted (odometry/odometry_config.h: its physics).

#include <cstddef>
#include <deque>
#include <functional>
#include <string>
#include <vector>

#include "drivers/frame_source.h"
#include "pipeline/pipeline.h"
#include "reloc/fern_encoder.h"
#include "reloc/relocaliser.h"
#include "runtime/frame_record.h"
#include "runtime/odometry_calibration.h"
#include "runtime/odometry_fusion.h"

namespace sb {

// What the runner knows of a frame's motion before it is resolved.
struct FrameMotion {
  Eigen::Isometry3d previousPose = Eigen::Isometry3d::Identity();  // the previous frame's final pose
  double previousStamp = 0.0;                                       // and its stamp (seconds)
  bool hasPrevious = false;                                         // false on the first frame
  std::optional<odometry::OdometryStep> step;  // the odometry's step since then (not rejected before ICP), calibrated
  std::optional<odometry::OdometryStep> raw;   // the same step as the wheels reported it
  std::optional<odometry::Level> level;        // the odometry's absolute tilt at this frame
};

class TrackingMonitor {
 public:
  explicit TrackingMonitor(const PipelineConfig& config);

  // Plain tracking is not trusted on the next frame (the frame's track is to be discarded).
  bool recovering() const { return recovering_; }
  // After the controller's decision on the frame in hand (rec.result, rec.decision): relocalises when
  // recovering, sets rec.state and rec.relocalisation, and overrides what a lost or relocalised frame may do
  // (no correction, no fusion, the next ICP from the held or relocalised pose).
  // `motion`: the previous frame's final pose and stamp, and the odometry's step since then when there is one.
  void resolve(Pipeline& pipeline, const DepthFrame& frame, double depthScale, FrameRecord& rec,
               const FrameMotion& motion);
  // After finishFrame: a good frame is offered to the keyframe database.
  void after(const DepthFrame& frame, double depthScale, FrameRecord& rec);

  const Relocaliser& relocaliser() const { return relocaliser_; }

  // Localising in a kept map (runtime/map_store.h; issue 55), called before the first frame: the relocaliser's
  // keyframes are seeded with the store's (its frame), and the run starts recovering (state lost, nothing fused)
  // without trying the held pose or the odometry's dead reckoning (both are in no frame of the store).
  // `prepare(pose)` runs before each ICP try from `pose` (it places the store's surface around it in the
  // volume); false: not this frame (the try fails without ICP). Each keyframe is also tried from
  // `offsetsM` along its view (a robot restarted on a path it drove, between two keyframes). A candidate must
  // hold kKeptMapConfirmFrames frames and, with odometry, move as the wheels do while it holds (within
  // kKeptMapOdometryToleranceM plus noise_per_m of the distance): another building's corridor can match a view
  // as well as the right place, but not the motion. Once a candidate is confirmed the run is localised: its
  // poses are in the store's frame and the monitor is as without a store.
  using KeptMapPrepare = std::function<bool(const Eigen::Isometry3d&)>;
  void startInKeptMap(const std::vector<Keyframe>& keyframes, KeptMapPrepare prepare,
                      const std::vector<double>& offsetsM = {});
  bool localisingInKeptMap() const { return static_cast<bool>(keptMapPrepare_); }
  // A run writing a kept map also harvests keyframes by distance (KeyframeDatabase::setMaxSpacing).
  void setKeyframeSpacing(double metres) { relocaliser_.setKeyframeSpacing(metres); }
  // The wheels' errors learnt so far; the runner corrects each odometry step with it.
  const odometry::OdometryCalibration& calibration() const { return calibration_; }

 private:
  // The tracked pose against the platform's physics: an impossible motion is discarded (tracked false).
  void checkPhysics(Pipeline& pipeline, FrameRecord& rec, const FrameMotion& motion);
  // The track discarded as implausible (`why`): the pose goes on at the last velocity, nothing fused.
  void discardTrack(Pipeline& pipeline, FrameRecord& rec, const FrameMotion& motion, const std::string& why);
  // A tracked frame with odometry: fused, or the odometry rejected as a slip.
  void fuse(FrameRecord& rec, const FrameMotion& motion);
  // A frame skipped by the tracking rate, with odometry: its pose is the last one moved by the wheels' step (in
  // state odometry, the dead reckoning goes on within its budget). Nothing fused.
  void followWheels(FrameRecord& rec, const FrameMotion& motion);
  // The frame's pose came from the wheels (a skipped frame, state odometry): its motion is the platform's velocity
  // the next frame's view is held against (inertia). Without it a view jumping ahead of a robot just back from the
  // odometry state had no velocity to break, and the wheels were rejected as a slip instead (a held-out drive:
  // 7.4 cm along the corridor at frame 56, kept for the whole drive).
  void movedBy(const FrameRecord& rec, const FrameMotion& motion);
  // A frame depth did not track, with odometry left in the budget: the pose follows it. False when it cannot.
  bool followOdometry(FrameRecord& rec, const FrameMotion& motion);
  // The relocaliser's try, refused when the odometry contradicts the candidate.
  TrackAttempt tryWithOdometry(const TrackAttempt& attempt) const;
  void relocalise(Pipeline& pipeline, const DepthFrame& frame, double depthScale, FrameRecord& rec,
                  const FrameMotion& motion);

  PipelineConfig config_;
  FernEncoder encoder_;
  Relocaliser relocaliser_;
  odometry::OdometryCalibration calibration_;
  int failedInARow_ = 0;
  bool recovering_ = false;
  TrackingState last_ = TrackingState::good;  // of the last frame with a tracking attempt
  // Frames in a row whose tracked motion the platform cannot make: the pose goes on at the last velocity and the
  // next frame tracks from there, up to this many (1 s at 30 Hz); then they count as failures (relocalisation).
  static constexpr int kMaxImplausibleInARow = 30;
  static constexpr size_t kAgreementFrames = 30;  // the recent tracked frames a jump's evidence is held against
  int implausibleInARow_ = 0;
  std::deque<double> agreement_;  // pair agreement of the last tracked frames (the evidence a jump must keep)
  std::optional<Eigen::Vector3d> lastVelocity_;  // m/s, world frame: of the last tracked frame's motion
  // Dead reckoning on the odometry since depth last tracked: the pose, the distance and time driven.
  std::optional<Eigen::Isometry3d> odometryPose_;
  double odometryDistanceM_ = 0.0, odometryTimeS_ = 0.0;
  // A kept map's verdict on the relocaliser's outcome: the candidate's motion against the wheels'.
  void keptMapVerdict(RelocaliseOutcome& outcome, const FrameMotion& motion);
  static constexpr int kKeptMapConfirmFrames = 15;          // 0.5 s at 30 Hz
  static constexpr double kKeptMapOdometryToleranceM = 0.05;
  KeptMapPrepare keptMapPrepare_;  // set while localising in a kept map
  std::optional<Eigen::Isometry3d> keptAnchor_;  // the pending candidate moved by the wheels since it was found
  double keptAnchorDistanceM_ = 0.0;
};

}  // namespace sb
