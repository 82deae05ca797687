#pragma once
// Tracking state and recovery for every controller (issue 29; tracking_state.h). The runner calls it on each
// frame:
//   trackFrame -> [recovering: the plain track is discarded] -> controller -> resolve() -> finishFrame -> after()
// Failed tracks in a row up to lost_after_failed_frames keep the controller's handling (its bounded
// extrapolation); from then on plain tracking is not trusted (a track from a stale pose after a kidnap can pass
// the residual and inlier tests in the wrong place): the pose is held, nothing is fused, and each frame the
// relocaliser (reloc/relocaliser.h) tries candidate poses until one is confirmed over consecutive frames.
// While tracking is good the frames feed the relocaliser's keyframes.
// The platform's motion (the odometry's fusion, the physics of a tracked motion) is the motion model's
// (odometry/motion_model.h): the monitor asks it to judge a track, to follow the wheels where depth does not
// track, where the dead reckoning is for the relocaliser's first guess, and whether the wheels contradict a
// candidate.

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "drivers/frame_source.h"
#include "pipeline/pipeline.h"
#include "reloc/fern_encoder.h"
#include "reloc/relocaliser.h"
#include "odometry/motion_model.h"
#include "runtime/frame_record.h"
#include "runtime/kept_map_history.h"

namespace sb {

class TrackingMonitor {
 public:
  explicit TrackingMonitor(const PipelineConfig& config);

  // Plain tracking is not trusted on the next frame (the frame's track is to be discarded).
  bool recovering() const { return recovering_; }
  // After the controller's decision on the frame in hand (rec.result, rec.decision): relocalises when
  // recovering, sets rec.state and rec.relocalisation, and overrides what a lost or relocalised frame may do
  // (no correction, no fusion, the next ICP from the held or relocalised pose). `model` judges the track and
  // follows the wheels (odometry/motion_model.h); `motion`: the frame's prediction, from the model.
  void resolve(Pipeline& pipeline, const DepthFrame& frame, double depthScale, FrameRecord& rec,
               odometry::MotionModel& model, const odometry::FrameMotion& motion);
  // After finishFrame: a good frame is offered to the keyframe database; rec.keptMap is set.
  void after(const DepthFrame& frame, double depthScale, FrameRecord& rec);

  const Relocaliser& relocaliser() const { return relocaliser_; }

  // Localising in a kept map (runtime/map_store.h; issue 55), called before the first frame: the relocaliser's
  // keyframes are seeded with the store's (its frame), and the run starts recovering (state lost, nothing fused)
  // without trying the held pose or the odometry's dead reckoning (both are in no frame of the store).
  // `prepare(pose)` runs before each ICP try from `pose` (it places the store's surface around it in the
  // volume); false: not this frame (the try fails without ICP). Each keyframe is also tried from
  // `offsetsM` along its view (a robot restarted on a path it drove, between two keyframes). A candidate must
  // hold kKeptMapConfirmFrames frames and, with odometry, move as the wheels do while it holds (within
  // kKeptMapOdometryToleranceM plus noise_per_m of the distance). With odometry the path the wheels drove behind
  // it decides instead of the count (kept_map_history.h, the constants below): another building's corridor end can
  // match a view as well as the right place, and move as the wheels do, but what the robot saw on its way there
  // does not fit the kept surface; its confirming frames then need only tracking's conditioning. Once a candidate
  // is confirmed the run is localised: its poses are in the store's frame and the monitor is as without a store.
  using KeptMapPrepare = std::function<bool(const Eigen::Isometry3d&)>;
  void startInKeptMap(const std::vector<Keyframe>& keyframes, KeptMapPrepare prepare,
                      const std::vector<double>& offsetsM = {});
  bool localisingInKeptMap() const { return static_cast<bool>(keptMapPrepare_); }
  // Relocalising over the whole map the run has made (a moving volume's kept slabs, runtime/map_store.h; Run wires
  // it): while recovering, and not localising in a kept map, `prepare(pose)` runs before each ICP try from `pose`
  // as a kept map's does (places the volume for it, fills it from the kept slabs; false: not this frame), and the
  // relocaliser rotates its candidates' order frame by frame, so that one placement a frame reaches each in turn.
  // Each keyframe is also tried from `offsetsM` along its view (a robot set down between two keyframes, as a
  // restarted one). Its bar, its confirmation over frames and the wheels' veto are unchanged: a look-alike is
  // refused as in the volume.
  void setRecoveryPrepare(KeptMapPrepare prepare, const std::vector<double>& offsetsM = {});
  // A run writing a kept map also harvests keyframes by distance (KeyframeDatabase::setMaxSpacing).
  void setKeyframeSpacing(double metres) { relocaliser_.setKeyframeSpacing(metres); }

 private:
  void relocalise(Pipeline& pipeline, const DepthFrame& frame, double depthScale, FrameRecord& rec,
                  odometry::MotionModel& model, const odometry::FrameMotion& motion);
  // A kept map's verdict on the relocaliser's outcome: the candidate's motion against the wheels', and before it
  // is accepted the path the wheels drove behind it against the kept surface (kept_map_history.h).
  void keptMapVerdict(RelocaliseOutcome& outcome, const odometry::FrameMotion& motion,
                      const odometry::OdometryConfig& odometry, const TryView& tryView);
  // Refuses the pending candidate (why: the reason, appended).
  void refuseKeptCandidate(RelocaliseOutcome& outcome, const std::string& why);

  PipelineConfig config_;
  FernEncoder encoder_;
  Relocaliser relocaliser_;
  // The pair agreement and model coverage (odometry/wheel_faults.h) of the recent good frames. A tracked frame
  // agreeing with under map_agreement_fraction of their median, where the model covers as much of the view as
  // usual, is tracked in the wrong place: ICP settled on the surfaces that look alike (a depth-only kidnap to a
  // look-alike stretch of corridor: 0.28 where the frames before had 0.70; issue 53 finding 7). A frame that
  // sees what the model does not hold yet (less coverage) says nothing of the place.
  std::optional<odometry::MapAgreement> goodAgreement_;  // made on the first tracked frame, from the model's config
  int failedInARow_ = 0;
  bool recovering_ = false;
  TrackingState last_ = TrackingState::good;  // of the last frame with a tracking attempt
  // Frames in a row whose tracked motion the platform cannot make: the pose goes on at the last velocity and the
  // next frame tracks from there, up to this many (1 s at 30 Hz); then they count as failures (relocalisation).
  static constexpr int kMaxImplausibleInARow = 30;
  int implausibleInARow_ = 0;
  static constexpr int kKeptMapConfirmFrames = 15;          // 0.5 s at 30 Hz
  static constexpr double kKeptMapOdometryToleranceM = 0.05;
  // The path check (kept_map_history.h): a candidate carried by the wheels is judged once it has held
  // kKeptMapPathConfirmFrames frames over at least kKeptMapPathMinM of the wheels' path (or when the relocaliser
  // would accept it): accepted when the kept surface covers earlier views back to kKeptMapPathMinM and each covered
  // one agrees within the sensor's noise at least kKeptMapPathAgreement, in place; refused when one does not, or
  // when it was confirmed at tracking's conditioning over too short a covered path (a robot that has hardly
  // moved is confirmed as without wheels: 15 frames at the relocaliser's conditioning). Three sigmas
  // of the sensor's noise fail a right pair rarely (0.3% a test for Gaussian noise): a view placed right fails
  // little more than what the kept surface smooths (its edges), a view placed in another building fails
  // wherever its surfaces are not the kept ones. The sensor's disparity noise when the config gives none:
  // the synthetic sensor's and about a Kinect v1's in its own image (pipeline/pair_noise.h).
  static constexpr double kKeptMapPathAgreement = 0.95;
  static constexpr double kKeptMapPathMinM = 1.0;
  static constexpr int kKeptMapPathConfirmFrames = 5;
  static constexpr double kKeptMapPathDisparityNoisePx = 0.062;
  KeptMapPrepare keptMapPrepare_;  // set while localising in a kept map
  KeptMapPrepare recoveryPrepare_;  // in-run recovery over the run's kept slabs (setRecoveryPrepare)
  std::vector<double> recoveryOffsetsM_;
  bool keptMapLocalised_ = false;  // a kept map's candidate was confirmed: poses are in the store's frame
  std::optional<Eigen::Isometry3d> keptAnchor_;  // the pending candidate moved by the wheels since it was found
  double keptAnchorDistanceM_ = 0.0;
  KeptMapHistory keptHistory_;  // the views and the wheels' path while localising in a kept map
  bool keptConfirmRelaxed_ = false;  // the pending candidate's confirming frames were held at tracking's bar
  bool keptPathShort_ = false;       // its path was judged too short to decide: judged again when accepted
};

}  // namespace sb
