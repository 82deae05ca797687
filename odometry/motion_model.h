#pragma once
// The platform's motion as the runtime sees it (docs/odometry.md): the robot's odometry (its stream, the
// calibration learnt of it, its prediction of each frame's motion and its fusion with the view), and the
// platform's physics (a tracked motion it cannot make is not trusted, with or without odometry). The runner
// asks it for each frame's prediction before tracking and hands it the view's result after the controller;
// the tracking monitor (runtime/tracking_monitor.h) keeps only the tracking state and the relocaliser, and
// asks it where the dead reckoning is and whether the wheels contradict a relocalisation.
//
//   FrameMotion m = model.predict(previousPose, previousStamp, hasPrevious, frame.timestamp, rec.odometry);
//   ... track from m.start(), controller ...
//   model.judge(pipeline, view, m);                 // fusion, slip, inertia, physics: may discard the track
//   if (tracked) model.viewFixed(view, m); else model.follow(view, m);  // the pose the frame ends with
//   model.finished(pose, stamp, viewFixed, rec.odometry);

#include <Eigen/Geometry>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "controller/controller.h"
#include "odometry/odometry_calibration.h"
#include "odometry/odometry_config.h"
#include "odometry/odometry_fusion.h"
#include "odometry/mount_calibration.h"
#include "odometry/odometry_track.h"
#include "odometry/time_offset.h"
#include "odometry/wheel_faults.h"
#include "pipeline/pipeline.h"

namespace sb::odometry {

// What the robot's odometry did for a frame (docs/odometry.md); all false/0 without odometry.
struct FrameOdometry {
  bool available = false;  // the odometry had a pose at this frame's stamp and at the previous frame's
  bool used = false;       // its motion seeded ICP and was fused with the tracked pose (or, state odometry, was it)
  bool rejected = false;   // contradicted by the view along the motions it fixes (a wheel slip): not used
  double driftM = 0.0;     // metres driven on odometry alone since depth last tracked (state odometry)
  bool fused = false;      // state odometry: the frame was fused at the odometry's pose (the view is back)
  // The camera's pose in the odometry frame at the frame's stamp (T_camera_to_odom), when available: the
  // odometry frame's z axis is up (REP 103), which the navigation map needs.
  std::optional<Eigen::Isometry3d> cameraToOdom;
  std::string why;         // when not available or rejected: why, for frames.jsonl
  WheelFault fault = WheelFault::none;  // the wheels and the view disagreeing (wheel_faults.h), after the frame
  // The wheels' errors learnt up to this frame (odometry_calibration.h), when the odometry had a step here:
  // the distance reads (1 + scale) times the truth, turns (1 + yawScale) times plus yawBias deg/s.
  std::optional<CalibrationEstimate> calibration;
};

// What is known of a frame's motion before it is resolved.
struct FrameMotion {
  Eigen::Isometry3d previousPose = Eigen::Isometry3d::Identity();  // the previous frame's final pose
  double previousStamp = 0.0;                                       // and its stamp (seconds)
  bool hasPrevious = false;                                         // false on the first frame
  std::optional<OdometryStep> step;  // the odometry's step since then (not rejected before ICP), calibrated
  std::optional<OdometryStep> raw;   // the same step as the wheels reported it, in the true camera frame (the mount
                                     // corrected, mount_calibration.h)
  std::optional<OdometryStep> reported;  // as reported, in the frame of the mount the odometry assumes
  // The wheels are at fault (slipping): their calibrated step, watched against the view but not used (`step` is
  // then empty).
  std::optional<OdometryStep> withheld;
  // The wheels' interval since the view last fixed the pose (distance, seconds), when the last frame's pose was
  // not the view's.
  double uncheckedM = 0.0, uncheckedS = 0.0;
  std::optional<Level> level;        // the odometry's absolute tilt at this frame
  // While the wheels are withheld: the height and tilt the base keeps, for ICP's solve (IcpStart::prior).
  std::optional<PlanarPrior> prior;
  // The odometry's prediction of this frame's pose (ICP starts there), when there is a step.
  std::optional<Eigen::Isometry3d> predicted() const {
    if (!step) return std::nullopt;
    return previousPose * step->delta;
  }

};

// The frame in hand as the model reads and amends it (the runtime's FrameRecord, borrowed).
struct FrameView {
  FrameResult& result;
  Decision& decision;
  FrameOdometry& odometry;
  std::string& implausible;  // why the tracked motion is one the platform cannot make; empty when it can
  // Tracks the frame in hand once more from a start pose (Pipeline::trackFrom at the frame's knobs); empty: the
  // model cannot (a unit test's frame without a pipeline behind it).
  std::function<TrackAttempt(const Eigen::Isometry3d& start)> trackFrom;
};

class MotionModel {
 public:
  explicit MotionModel(const OdometryConfig& config);

  // The robot's odometry, shared with whoever adds samples (the daemon's socket); nullptr: none.
  void setTrack(std::shared_ptr<const OdometryTrack> track) { track_ = std::move(track); }
  const OdometryTrack* track() const { return track_.get(); }
  const OdometryConfig& config() const { return config_; }
  // The wheels' errors learnt so far; every step taken from the odometry is corrected by them.
  const OdometryCalibration& calibration() const { return calibration_; }
  // The camera mount's error learnt so far; every step is corrected by it first.
  const MountCalibration& mount() const { return mount_; }
  // Starts from what an earlier run learnt (a map store, runtime/kept_odometry.h): the wheels' calibration, the
  // mount's correction, the odometry's clock (false when this run's config does not take it: TimeOffset::restore).
  void restoreCalibration(const CalibrationState& calibration) { calibration_.restore(calibration); }
  void restoreMount(const MountCalibration::State& mount) { mount_.restore(mount); }
  bool restoreTimeOffset(const TimeOffset::State& kept) { return timeOffset_.restore(kept); }
  // The odometry's clock against the frames' learnt so far; every step is read at the frames' stamps plus it.
  const TimeOffset& timeOffset() const { return timeOffset_; }

  // The frame at `stamp`: the previous frame's final pose and stamp, and the odometry's step since then
  // (calibrated, its noise widened over the frames the view did not fix); `out` says what the odometry had.
  FrameMotion predict(const Eigen::Isometry3d& previousPose, double previousStamp, bool hasPrevious, double stamp,
                      FrameOdometry& out) const;

  // A tracked frame: with odometry the view and the wheels are weighed; where they disagree along a motion the
  // view fixes, physics says who is wrong (inertia, the platform's limits). A track found wrong is discarded
  // (view.result.tracked false, view.implausible says why).
  void judge(Pipeline& pipeline, const FrameView& view, const FrameMotion& motion);
  // The view fixed the frame (tracked and kept): the dead reckoning ends, the velocity is the frame's.
  void viewFixed(const FrameView& view, const FrameMotion& motion);
  // The frame did not track: with odometry left in the budget its pose follows the wheels (true; state
  // odometry). False when it cannot.
  bool follow(const FrameView& view, const FrameMotion& motion);
  // A frame skipped by the tracking rate: its pose is the last one moved by the wheels' step (`deadReckoning`:
  // the dead reckoning of state odometry goes on within its budget). Nothing fused. False when the view has not
  // checked the pose for longer than max_unchecked_s: the frame is not the view's word (state odometry).
  bool skipped(const FrameView& view, const FrameMotion& motion, bool deadReckoning);
  // The next frame must be tracked whatever the tracking rate: the view last checked the wheels too long ago, or
  // the two dispute the motion (a frame skipped then would follow the wheels it disputes).
  bool needsView() const { return needsView_ || faults_.fault() == WheelFault::disputed; }

  // The wheels and the view disagree (wheel_faults.h): while `disputed` no pose is good and nothing is fused;
  // `kidnapped`: the relocaliser searches the whole map.
  WheelFault fault() const { return faults_.fault(); }

  // The frame's depth: `blank` when it holds almost no reading (a covered lens, kBlankShare). After a blank
  // spell, until the view fixes the pose again, a view the model covers less than usual may be fused at the
  // wheels' pose though it does not hold the map (wheel_faults.h uncontradicted): the region ahead was mapped
  // before the cover only from afar, and without it the view never tracks again (a 0.67 s cover: pair agreement
  // 0.30-0.34 against a floor of 0.33 for the rest of the drive). A view present all along and contradicted (a
  // carried robot's, set down where its wheels' pose looks into unmapped space) is not fused.
  void depthSeen(bool blank) {
    blank_ = blank;
    if (blank) afterBlank_ = true;
  }
  static constexpr double kBlankShare = 0.05;  // of the pixels with a reading
  // The frame's depth as the model reads it: blank or not (above), and, while the mount's tilt is learnt from the
  // floor (mount_calibration.h, floor_up.h), the floor's up against the up of the mount the wheels assume.
  // `depthScale`: raw units per metre; `k`: the depth image's intrinsics.
  void depthSeen(const DepthRaw& depth, double depthScale, const Intrinsics& k, const FrameMotion& motion);

  // While the tracker is lost: the dead reckoning goes on (the relocaliser's first guess).
  void deadReckon(const FrameMotion& motion);
  // The dead-reckoned pose since depth last tracked, and the distance driven on it.
  const std::optional<Eigen::Isometry3d>& deadReckoned() const { return odometryPose_; }
  double deadReckonedM() const { return odometryDistanceM_; }
  // A relocalisation's attempt, refused (tracked false) when the wheels say the camera is elsewhere.
  TrackAttempt vet(const TrackAttempt& attempt) const;
  // The relocaliser placed the camera: the dead reckoning ends.
  void relocalised();

  // The frame's final pose and stamp; `viewFixed`: the view fixed it (for the next prediction's noise and the
  // odometry's tilt).
  void finished(const Eigen::Isometry3d& pose, double stamp, bool viewFixed, const FrameOdometry& odometry);

 private:
  // The tracked pose against the platform's physics: an impossible motion is discarded (tracked false).
  void checkPhysics(Pipeline& pipeline, const FrameView& view, const FrameMotion& motion);
  // The track discarded as implausible (`why`): the pose goes on at the last velocity, nothing fused.
  void discardTrack(Pipeline& pipeline, const FrameView& view, const FrameMotion& motion, const std::string& why);
  // A frame depth did not track, with odometry left in the budget: the pose follows it. False when it cannot.
  bool followOdometry(const FrameView& view, const FrameMotion& motion);
  // The frame's pose came from the wheels (a skipped frame, state odometry): its motion is the platform's velocity
  // the next frame's view is held against (inertia). Without it a view jumping ahead of a robot just back from the
  // odometry state had no velocity to break, and the wheels were rejected as a slip instead (a held-out drive:
  // 7.4 cm along the corridor at frame 56, kept for the whole drive).
  void movedBy(const FrameView& view, const FrameMotion& motion);

  // Without the fault watch (dispute_s 0): the tracked frame fused with the wheels, a disagreement decided by one
  // frame's inertia or the platform's limits.
  void judgeByInertia(Pipeline& pipeline, const FrameView& view, const FrameMotion& motion);
  // The fault watch is on (odometry.dispute_s > 0; wheel_faults.h).
  bool faultsOn() const { return config_.disputeS > 0.0; }
  // The mount's error is learnt (and corrected: predict) with the watch on, unless the mount is taken as exact
  // (mount_sigma_deg 0).
  bool learnsMount() const { return faultsOn() && config_.mountSigmaDeg > 0.0; }
  // A tracked frame with odometry (or a fault open): judged against the map, then against the wheels (`wheels`:
  // the step used, or the one withheld while slipping): fused when they agree, the view's pose unfused while a
  // dispute is open.
  void judgeAgainstWheels(Pipeline& pipeline, const FrameView& view, const FrameMotion& motion,
                          const std::optional<OdometryStep>& wheels);

  // The view's own prediction: where the last frames the view fixed in agreement with the wheels put the camera at
  // `stamp`, moving on at their velocity; none when they are older than kViewPredictionS.
  std::optional<Eigen::Isometry3d> viewPrediction(double stamp) const;
  // A frame whose track from the wheels' prediction is in doubt (it failed, it does not hold the map, a dispute is
  // open, or the wheels' prediction and the view's own are apart): tracked again from the view's own prediction,
  // and that track made the frame's when it holds the map better. True when it was.
  bool trackFromViewMotion(Pipeline& pipeline, const FrameView& view, const FrameMotion& motion);
  static constexpr double kViewPredictionS = 0.5;
  static constexpr double kPredictionsApartM = 0.02, kPredictionsApartDeg = 1.0;
  // Two tracks this close met: ICP's own noise is millimetres.
  static constexpr double kTracksMetM = 0.005, kTracksMetDeg = 0.3;

  // The view at `stamp` corrects the wheels' prediction as it did on the frames before (wheel_faults.h steady):
  // its pose stands.
  bool steadyCorrection(double stamp, const Eigen::Isometry3d& tracked, const Eigen::Isometry3d& predicted,
                        const FrameMotion& motion, const OdometryStep& wheels);
  // The view stands where it last fixed the pose (within kStillM, kStillDeg: a tracked view's noise is
  // millimetres) while the wheels moved at least twice that since: a stall's signature.
  bool viewStill(const Eigen::Isometry3d& tracked, const FrameMotion& motion, const OdometryStep& wheels) const;
  static constexpr double kStillM = 0.01, kStillDeg = 0.5;
  // The direction the view moved the wheels' prediction on the dispute's last contradicting frame (world frame,
  // the camera centre's offset over kStillM), and whether this frame's view fixes that motion: only such a view's
  // agreement with the wheels settles the dispute (a frame of a view that leaves it free is neither side's).
  void disputedAlong(const Eigen::Isometry3d& tracked, const Eigen::Isometry3d& predicted);
  bool settles(const TrackingQuality& quality) const;
  std::optional<Eigen::Vector3d> disputed_;

  OdometryConfig config_;
  std::shared_ptr<const OdometryTrack> track_;
  OdometryCalibration calibration_;
  MountCalibration mount_;
  TimeOffset timeOffset_;
  static constexpr size_t kAgreementFrames = 30;  // the recent tracked frames a jump's evidence is held against
  std::deque<double> agreement_;  // pair agreement of the last tracked frames (the evidence a jump must keep)
  MapAgreement mapAgreement_;     // of the recent frames the view fixed without dispute
  FaultWatch faults_;
  TurnCorrections turnCorrections_;  // the view's corrections of the wheels' turn over the last second
  bool held_ = false;             // the last judged frame's view held the map
  bool needsView_ = false;
  std::optional<Velocity> lastVelocity_;  // of the last frame's motion (tracked, or moved by the wheels)
  // The covariance of the last fused frame's pose and its stamp: the next frame's prior when it is that frame.
  std::optional<Matrix6> fusedCovariance_;
  double fusedStamp_ = 0.0;
  // fusedCovariance_ when the frame before `motion`'s was fused (then reset: a frame not fused leaves none).
  std::optional<Matrix6> takeFusedCovariance(const FrameMotion& motion);
  void keepFusedCovariance(const Fusion& fused, double stamp);  // a frame fused at `stamp`
  // Dead reckoning on the odometry since depth last tracked: the pose, the distance and time driven.
  std::optional<Eigen::Isometry3d> odometryPose_;
  double odometryDistanceM_ = 0.0, odometryTimeS_ = 0.0;
  // The last frame whose pose the view fixed, for the noise of the wheels' prediction, and whether it was the
  // last frame.
  std::optional<double> viewStamp_;
  std::optional<Eigen::Isometry3d> lastViewPose_;  // the pose of the last frame the view fixed (holding the map)
  double lastViewStamp_ = 0.0;                     // and its stamp
  // The last frame the view fixed in agreement with the wheels (no dispute), and the velocity between the last two
  // (at most kViewPredictionS apart): the body's motion as the view measured it before wheels went wrong.
  std::optional<Eigen::Isometry3d> agreedPose_;
  double agreedStamp_ = 0.0;
  std::optional<Velocity> viewVelocity_;
  bool viewPredicted_ = false;  // this frame's track is the one from the view's own prediction
  bool viewMet_ = false;        // its tracks from the wheels' prediction and the view's own met (the view fixes it)
  std::string viewPredictedWhy_;  // and why, for frames.jsonl
  std::optional<double> firstStamp_;  // the run's first frame (the map's origin): unchecked time counts from it
  bool previousViewFixed_ = false;
  bool afterBlank_ = false;  // a blank frame since the view last fixed the pose (depthSeen)
  bool blank_ = false;       // this frame's depth is blank (depthSeen)
  // Where the odometry's absolute tilt is anchored: frames the view fixed with an odometry pose, their pose and the
  // odometry's (as reported). The odometry frame in the world frame (its up axis) follows from one of them and the
  // mount's correction. A mount error tilts the odometry's camera by the chord of the base's turn since the anchor
  // (odometry_config.h mount_sigma_deg), the same on every frame: a bias that repeated frames do not average out.
  // So a frame is levelled only by an anchor within maxAnchorTurnRad() of its heading (where that bias stays under
  // tilt_sigma_deg), and a frame the view fixes farther from every anchor becomes one (the way back of a U-turn)
  // once the base holds its heading (turned at most kSteadyTurnDeg over the last kSteadyS). Anchors taken while
  // turning chain, each inheriting the tilt the one before pulled the pose to (tried on a mount drive: 59 `good`
  // frames over 0.5 m off, DEFAULT; anchored only on a held heading, none).
  struct TiltAnchor {
    Eigen::Isometry3d pose, cameraToOdom;
  };
  std::vector<TiltAnchor> anchors_;
  static constexpr double kSteadyTurnDeg = 2.0, kSteadyS = 1.0;
  std::deque<std::pair<double, Eigen::Matrix3d>> recentHeading_;  // the odometry's camera rotation, last kSteadyS
  bool headingSteady(double stamp, const Eigen::Isometry3d& cameraToOdom);
  static constexpr size_t kMaxAnchors = 256;  // a bound: each reaches at least 0.6 degrees at the widest mount_sigma_deg
  double maxAnchorTurnRad() const;
  // The anchor nearest in heading to `cameraToOdom` and the turn from it, or nullptr when none is within reach.
  const TiltAnchor* nearestAnchor(const Eigen::Isometry3d& cameraToOdom, double& turnRad) const;
};

}  // namespace sb::odometry
