#include "odometry/motion_model.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "odometry/floor_up.h"
#include "odometry/format_numbers.h"

namespace sb::odometry {

namespace {

// The pose a frame ends with, as the decision stands.
const Eigen::Isometry3d& finalPose(const FrameView& view) {
  if (view.decision.correctedPose) return *view.decision.correctedPose;
  if (view.decision.refinedPose) return *view.decision.refinedPose;
  return view.result.T_camera_to_world;
}

}  // namespace

MotionModel::MotionModel(const OdometryConfig& config)
    : config_(config),
      calibration_(config),
      timeOffset_(config),
      mapAgreement_(config.mapAgreementFraction),
      faults_(config.disputeS, config.calmS) {}

FrameMotion MotionModel::predict(const Eigen::Isometry3d& previousPose, double previousStamp, bool hasPrevious,
                                 double stamp, FrameOdometry& out) const {
  FrameMotion motion;
  motion.previousPose = previousPose;
  motion.previousStamp = previousStamp;
  motion.hasPrevious = hasPrevious;
  if (!track_) return motion;
  if (!motion.hasPrevious) {
    out.why = "first frame: no motion yet";
    return motion;
  }
  const OdometryConfig& c = config_;
  const double offset = timeOffset_.offset();  // the odometry's clock: its instant of each frame's stamp
  out.cameraToOdom = track_->poseAt(stamp + offset, c.maxGapS, c.maxExtrapolationS);
  auto step = stepBetween(*track_, previousStamp + offset, stamp + offset, c, out.why);
  if (!step) return motion;
  out.available = true;
  // A step the platform cannot make is the wheels slipping (or a glitch), not motion.
  const std::string slip = implausibleMotion(c, Eigen::Isometry3d::Identity(), step->delta, step->dt, std::nullopt);
  if (!slip.empty()) {
    out.rejected = true;
    out.why = "the odometry's step " + slip + ": a wheel slip, not used";
    return motion;
  }
  out.calibration = calibration_.estimate();
  motion.reported = step;
  motion.raw = faultsOn() ? mount_.correct(*step) : *step;
  motion.step = calibration_.correct(*motion.raw);
  if (faults_.fault() == WheelFault::slipping) {  // watched, not used
    motion.withheld = motion.step;
    motion.step.reset();
    // The base's height and tilt are not the wheels' word: they hold while the wheels are withheld.
    if (agreedPose_ && c.planarPriorConditioning > 0)
      motion.prior = PlanarPrior{*agreedPose_, agreedPose_->linear() * motion.withheld->up, c.planarPriorConditioning};
    return motion;
  }
  double turnRad = 0.0;  // the base's turn since the anchor: a mount error tilts the odometry's camera by its chord
  if (const TiltAnchor* anchor = out.cameraToOdom ? nearestAnchor(*out.cameraToOdom, turnRad) : nullptr) {
    Eigen::Isometry3d E = Eigen::Isometry3d::Identity();  // the odometry's absolute tilt
    E.linear() = mount_.correction();
    const Eigen::Isometry3d worldFromOdometry = anchor->pose * E * anchor->cameraToOdom.inverse();
    motion.level = Level{worldFromOdometry * *out.cameraToOdom * E.inverse(),
                         worldFromOdometry.linear() * Eigen::Vector3d::UnitZ(),
                         levelSigmaRad(c.tiltSigmaDeg, mount_.sigmaDeg(c.mountSigmaDeg), turnRad)};
  }
  if (viewStamp_ && !previousViewFixed_) {
    // The last frame's pose was not the view's (skipped by the tracking rate, dead reckoning in state odometry,
    // a discarded track): the prediction is as uncertain as the wheels' whole interval since the view last fixed
    // the pose, not one step of it.
    std::string why;
    if (const auto interval = stepBetween(*track_, *viewStamp_ + offset, stamp + offset, c, why)) {
      widenNoise(*motion.step, *interval);
      motion.uncheckedM = interval->distanceM();
      motion.uncheckedS = interval->dt;
    }
  } else if (!viewStamp_ && firstStamp_) {  // the view has fixed no frame since the first
    motion.uncheckedS = stamp - *firstStamp_;
  }
  return motion;
}

void MotionModel::depthSeen(const DepthRaw& depth, double depthScale, const Intrinsics& k, const FrameMotion& motion) {
  const auto& px = depth.pixels();
  const auto readings = std::count_if(px.begin(), px.end(), [](uint16_t v) { return v != 0; });
  depthSeen(static_cast<double>(readings) < kBlankShare * static_cast<double>(px.size()));
  if (!learnsMount() || !motion.reported || !mount_.wantsFloor() || blank_) return;
  if (const std::optional<FloorUp> floor = floorUp(depth, depthScale, k, motion.reported->up))
    mount_.floorSeen(floor->up, motion.reported->up);
}

void MotionModel::judge(Pipeline& pipeline, const FrameView& view, const FrameMotion& motion) {
  FrameResult& r = view.result;
  Decision& d = view.decision;
  needsView_ = false;
  viewMet_ = false;
  viewPredicted_ = faultsOn() && trackFromViewMotion(pipeline, view, motion);
  held_ = r.tracked && mapAgreement_.holds(r.pairAgreement);
  const std::optional<OdometryStep>& wheels = motion.withheld ? motion.withheld : motion.step;
  const bool watching = wheels || faults_.fault() != WheelFault::none;
  if (!faultsOn()) {
    judgeByInertia(pipeline, view, motion);
    return;
  }
  if (r.tracked && !watching) {
    if (!d.correctedPose && motion.hasPrevious) checkPhysics(pipeline, view, motion);
  } else if (r.tracked) {
    judgeAgainstWheels(pipeline, view, motion, wheels);
  }
  view.odometry.fault = faults_.fault();
  if (faults_.fault() == WheelFault::none) disputed_.reset();
  if (faults_.fault() != WheelFault::none && view.odometry.why.empty()) view.odometry.why = faults_.why();
  if (viewPredicted_)
    view.odometry.why = viewPredictedWhy_ + (view.odometry.why.empty() ? "" : "; " + view.odometry.why);
}

void MotionModel::viewFixed(const FrameView& view, const FrameMotion& motion) {
  const FrameResult& r = view.result;
  agreement_.push_back(r.pairAgreement);
  if (agreement_.size() > kAgreementFrames) agreement_.pop_front();
  odometryPose_.reset();
  // The dead-reckoning budget ends only where the view fixed the pose with evidence: it holds the map and no
  // dispute is open (a frame that merely tracked between frames on the wheels does not restart it).
  if (!faultsOn() || (held_ && !view.odometry.rejected)) {
    if (faults_.fault() == WheelFault::none) {
      mapAgreement_.add(r.pairAgreement);
      mapAgreement_.addCoverage(r.modelCoverage);
    }
    odometryDistanceM_ = odometryTimeS_ = 0.0;
  }
  if (held_) {  // the view fixed this pose (whether or not the wheels agreed): a stall is judged frame to frame
    afterBlank_ = false;
    lastViewPose_ = finalPose(view);
    lastViewStamp_ = r.timestamp;
  }
  if (held_ && !view.odometry.rejected && faults_.fault() == WheelFault::none) {
    // The view's own motion is learnt where it agreed with the wheels: a view that ran away from them (a coarse
    // view matching the model 0.1 m ahead of a creeping robot) does not set the velocity it is then predicted by.
    const double since = r.timestamp - agreedStamp_;
    if (agreedPose_ && since > 0 && since <= kViewPredictionS)
      viewVelocity_ = velocityBetween(*agreedPose_, finalPose(view), since);
    else
      viewVelocity_.reset();
    agreedPose_ = finalPose(view);
    agreedStamp_ = r.timestamp;
  }
  const double dt = r.timestamp - motion.previousStamp;
  if (viewPredicted_ && viewVelocity_)  // the frames between were the wheels' word: the view's own velocity stands
    lastVelocity_ = viewVelocity_;
  else if (motion.hasPrevious && dt > 0)
    lastVelocity_ = velocityBetween(motion.previousPose, finalPose(view), dt);
  else
    lastVelocity_.reset();
}

bool MotionModel::follow(const FrameView& view, const FrameMotion& motion) {
  const FrameResult& r = view.result;
  if (view.implausible.empty()) {  // depth failed to track (not a discarded view)
    lastVelocity_.reset();
    faults_.interrupt();
  }
  // A track that failed while the model was in view and the view disagreed with it: the robot is not where the
  // wheels say (evidence of a kidnap); one that failed on a blind or new view says nothing.
  if (faultsOn() && motion.step && r.trackingAttempted && view.implausible.empty() &&
      mapAgreement_.contradicted(r.pairAgreement, r.modelCoverage))
    faults_.viewContradicted(r.timestamp);
  else
    faults_.expire(r.timestamp);
  view.odometry.fault = faults_.fault();
  if (!motion.step || faults_.fault() == WheelFault::kidnapped) return false;
  if (!followOdometry(view, motion)) {
    if (faults_.concludeKidnapped()) {
      view.odometry.fault = faults_.fault();
      view.odometry.why = faults_.why();
    }
    return false;
  }
  movedBy(view, motion);
  return true;
}

bool MotionModel::skipped(const FrameView& view, const FrameMotion& motion, bool deadReckoning) {
  if (!motion.step) return true;
  needsView_ = motion.uncheckedS > config_.maxUncheckedS;
  if (deadReckoning) {  // depth could not track: the dead reckoning and its budget go on
    if (followOdometry(view, motion)) movedBy(view, motion);
    return true;
  }
  // Between two tracked frames the wheels carry the pose: one frame of a calibrated step is millimetres off.
  Decision& d = view.decision;
  d.correctedPose = motion.predicted();
  d.refinedPose.reset();
  d.integrate = false;
  d.keepReference = true;  // the next tracked frame pairs with the last raycast, as after any unfused frame
  d.nextStartPose.reset();
  view.odometry.used = true;
  movedBy(view, motion);
  return !needsView_;
}

void MotionModel::deadReckon(const FrameMotion& motion) {
  if (!motion.step) return;
  odometryPose_ = odometryPose_.value_or(motion.previousPose) * motion.step->delta;
  odometryDistanceM_ += motion.step->distanceM();
  odometryTimeS_ += motion.step->dt;
}

void MotionModel::relocalised() {
  afterBlank_ = false;
  lastViewPose_.reset();
  agreedPose_.reset();
  viewVelocity_.reset();
  turnCorrections_.clear();
  disputed_.reset();
  odometryPose_.reset();
  odometryDistanceM_ = odometryTimeS_ = 0.0;
  faults_.reset();
}

void MotionModel::finished(const Eigen::Isometry3d& pose, double stamp, bool viewFixed, const FrameOdometry& odometry) {
  previousViewFixed_ = viewFixed;
  if (viewFixed) viewStamp_ = stamp;
  if (!firstStamp_) firstStamp_ = stamp;
  // The odometry frame in the world frame, from the first frame the view fixed with an odometry pose, and again
  // from one the view fixed where the base has turned beyond every anchor's reach.
  double turnRad = 0.0;
  if (!odometry.cameraToOdom) return;
  const bool steady = headingSteady(stamp, *odometry.cameraToOdom);
  if (viewFixed && anchors_.size() < kMaxAnchors && (anchors_.empty() || steady) &&
      !nearestAnchor(*odometry.cameraToOdom, turnRad))
    anchors_.push_back(TiltAnchor{pose, *odometry.cameraToOdom});
}

bool MotionModel::headingSteady(double stamp, const Eigen::Isometry3d& cameraToOdom) {
  recentHeading_.emplace_back(stamp, cameraToOdom.linear());
  while (!recentHeading_.empty() && recentHeading_.front().first < stamp - kSteadyS) recentHeading_.pop_front();
  if (recentHeading_.front().first > stamp - 0.9 * kSteadyS) return false;  // not a whole window yet
  const double turn = Eigen::AngleAxisd(recentHeading_.front().second.transpose() * cameraToOdom.linear()).angle();
  return turn <= kSteadyTurnDeg * M_PI / 180.0;
}

double MotionModel::maxAnchorTurnRad() const {
  // The turn at which a mount off by its sigma tilts the odometry's camera by tilt_sigma_deg: 2 sin(turn / 2) e.
  const double mountDeg = mount_.sigmaDeg(config_.mountSigmaDeg);
  if (config_.tiltSigmaDeg <= 0.0 || mountDeg <= 0.5 * config_.tiltSigmaDeg) return M_PI;
  return 2.0 * std::asin(config_.tiltSigmaDeg / (2.0 * mountDeg));
}

const MotionModel::TiltAnchor* MotionModel::nearestAnchor(const Eigen::Isometry3d& cameraToOdom,
                                                          double& turnRad) const {
  const TiltAnchor* best = nullptr;
  for (const TiltAnchor& a : anchors_) {
    const double turn = Eigen::AngleAxisd(a.cameraToOdom.linear().transpose() * cameraToOdom.linear()).angle();
    if (!best || turn < turnRad) {
      best = &a;
      turnRad = turn;
    }
  }
  return best && turnRad <= maxAnchorTurnRad() ? best : nullptr;
}

void MotionModel::checkPhysics(Pipeline& pipeline, const FrameView& view, const FrameMotion& motion) {
  FrameResult& r = view.result;
  const OdometryConfig& c = config_;
  const double dt = r.timestamp - motion.previousStamp;
  std::optional<Eigen::Vector3d> lastLinear;
  if (lastVelocity_) lastLinear = lastVelocity_->linear;
  const std::string why = implausibleMotion(c, motion.previousPose, r.T_camera_to_world, dt, lastLinear);
  if (why.empty()) return;
  // The estimate catching up (the view agrees as well as before, within ICP's reach): it stands.
  const double excess =
      (r.T_camera_to_world.translation() - motion.previousPose.translation()).norm() - c.maxSpeedMPerS * dt;
  if (!agreement_.empty() && excess <= c.maxCorrectionM) {
    std::vector<double> recent(agreement_.begin(), agreement_.end());
    std::nth_element(recent.begin(), recent.begin() + recent.size() / 2, recent.end());
    if (r.pairAgreement >= recent[recent.size() / 2] - c.jumpAgreementMargin) return;
  }
  discardTrack(pipeline, view, motion, why);
}

void MotionModel::discardTrack(Pipeline& pipeline, const FrameView& view, const FrameMotion& motion,
                               const std::string& why) {
  // Not a motion this platform makes: the view matched the model somewhere else (a runaway, a spliced frame).
  // Discarded like a failed track: the pose goes on at the last velocity (or follows the odometry), nothing
  // fused, and the next frame tracks from there; a run of them ends as failures (relocalisation).
  FrameResult& r = view.result;
  const double dt = r.timestamp - motion.previousStamp;
  view.implausible = why;
  pipeline.discardTrack(r);
  Decision& d = view.decision;
  // The pose goes on at the last plausible velocity (held without one), the rotation held.
  Eigen::Isometry3d extrapolated = motion.previousPose;
  if (lastVelocity_ && dt > 0) extrapolated.translation() += lastVelocity_->linear * dt;
  d.correctedPose = extrapolated;
  d.refinedPose.reset();
  d.integrate = false;
  d.keepReference = false;
  d.nextStartPose.reset();
}

void MotionModel::movedBy(const FrameView& view, const FrameMotion& motion) {
  const double dt = view.result.timestamp - motion.previousStamp;
  if (view.decision.correctedPose && dt > 0)
    lastVelocity_ = velocityBetween(motion.previousPose, *view.decision.correctedPose, dt);
}

bool MotionModel::followOdometry(const FrameView& view, const FrameMotion& motion) {
  const OdometryConfig& c = config_;
  const OdometryStep& step = *motion.step;
  const Eigen::Isometry3d pose = odometryPose_.value_or(motion.previousPose) * step.delta;
  const double distance = odometryDistanceM_ + step.distanceM();
  const double time = odometryTimeS_ + step.dt;
  odometryPose_ = pose;
  odometryDistanceM_ = distance;
  odometryTimeS_ = time;
  view.odometry.driftM = distance;
  if (distance > c.maxDistanceM || time > c.maxTimeS) {
    view.odometry.why = formatNumbers("odometry alone for %.2f m, %.1f s: beyond its bound (max_distance_m, max_time_s)",
                               distance, time);
    return false;
  }
  Decision& d = view.decision;
  d.correctedPose = pose;
  d.refinedPose.reset();
  // A covered lens or a blank view: nothing fused. When the view is back but the model in it is too sparse to
  // track against (the volume moved on while the camera was blind, the region ahead was never mapped), the
  // frame is fused at the odometry's pose, within its drift bound: the map's weights keep what it held, the
  // holes fill, and the next frame tracks against it. Also where the model in view is empty (no pair at all):
  // that was once taken for a blank view, and a volume that had shifted into unmapped space while the lens was
  // covered stayed empty until the budget ran out (a held-out drive, `adaptive`: lost 0.5 s after the cover).
  view.odometry.fused = view.result.trackingAttempted && !blank_ &&
                        view.implausible.empty() &&
                        (!faultsOn() || ((faults_.fault() == WheelFault::none || faults_.unsupported()) &&
                                         (afterBlank_ ? mapAgreement_.uncontradicted(
                                                            view.result.pairAgreement,
                                                            view.result.modelCoverage)
                                                      : mapAgreement_.holds(view.result.pairAgreement))));
  d.integrate = view.odometry.fused;
  d.keepReference = false;
  d.nextStartPose.reset();
  view.odometry.used = true;
  return true;
}

TrackAttempt MotionModel::vet(const TrackAttempt& attempt) const {
  // Kidnapped: the view showed the robot is not where the wheels say, so they cannot refuse a candidate the
  // view confirms (the relocaliser's confirmation over consecutive frames still holds).
  if (!odometryPose_ || !attempt.tracked || faults_.fault() == WheelFault::kidnapped) return attempt;
  const double tolerance = config_.relocaliseToleranceM + config_.noisePerM * odometryDistanceM_;
  if ((attempt.T_camera_to_world.translation() - odometryPose_->translation()).norm() <= tolerance) return attempt;
  TrackAttempt refused = attempt;  // the wheels say the camera is elsewhere: a repeating place, not this one
  refused.tracked = false;
  return refused;
}

}  // namespace sb::odometry
