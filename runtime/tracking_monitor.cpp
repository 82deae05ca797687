#include "runtime/tracking_monitor.h"

#include <algorithm>
#include <cstdio>
#include <vector>

namespace sb {

namespace {

std::string format(const char* fmt, double a, double b) {
  char buf[160];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}

// The pose a frame ends with, as the decision stands.
const Eigen::Isometry3d& finalPose(const FrameRecord& rec) {
  if (rec.decision.correctedPose) return *rec.decision.correctedPose;
  if (rec.decision.refinedPose) return *rec.decision.refinedPose;
  return rec.result.T_camera_to_world;
}

}  // namespace

TrackingMonitor::TrackingMonitor(const PipelineConfig& config)
    : config_(config),
      encoder_(FernParams{}),
      relocaliser_(RelocaliserParams(config)),
      calibration_(config.odometry) {}

void TrackingMonitor::resolve(Pipeline& pipeline, const DepthFrame& frame, double depthScale, FrameRecord& rec,
                              const FrameMotion& motion) {
  FrameResult& r = rec.result;
  Decision& d = rec.decision;
  if (!r.trackingAttempted && !recovering_) {  // bootstrap, or a frame skipped by the tracking rate
    rec.state = last_ == TrackingState::relocalised ? TrackingState::good : last_;
    if (motion.step && r.frame >= static_cast<size_t>(config_.bootstrapFrames)) followWheels(rec, motion);
    return;
  }
  if (recovering_) {
    if (motion.step && !localisingInKeptMap()) {  // dead reckoning goes on while lost: the relocaliser's first guess
      odometryPose_ = odometryPose_.value_or(motion.previousPose) * motion.step->delta;
      odometryDistanceM_ += motion.step->distanceM();
      odometryTimeS_ += motion.step->dt;
    }
    relocalise(pipeline, frame, depthScale, rec, motion);
    return;
  }
  if (r.tracked && motion.step) {
    // With odometry the view and the wheels are weighed first; where they disagree along a motion the view
    // fixes, physics says who is wrong: a tracked motion that departs further from the last velocity than the
    // wheels' (inertia), or one the platform cannot make, is the view's error (the pose follows the odometry
    // below); otherwise the wheels slipped (the tracked pose stands).
    fuse(rec, motion);
    if (rec.odometry.rejected && !d.correctedPose) {
      const double dt = r.timestamp - motion.previousStamp;
      const std::string inertia =
          odometry::viewBreaksInertia(motion.previousPose, d.refinedPose ? *d.refinedPose : r.T_camera_to_world,
                                      motion.previousPose * motion.step->delta, dt, lastVelocity_,
                                      config_.odometry.slipFloorM);
      if (!inertia.empty())
        discardTrack(pipeline, rec, motion, inertia);
      else
        checkPhysics(pipeline, rec, motion);
      if (!r.tracked) {
        rec.odometry.rejected = false;
        rec.odometry.why.clear();
      }
    }
  } else if (r.tracked && !d.correctedPose && motion.hasPrevious) {
    checkPhysics(pipeline, rec, motion);
  }
  if (r.tracked) {
    failedInARow_ = 0;
    implausibleInARow_ = 0;
    agreement_.push_back(r.pairAgreement);
    if (agreement_.size() > kAgreementFrames) agreement_.pop_front();
    odometryPose_.reset();
    odometryDistanceM_ = odometryTimeS_ = 0.0;
    const double dt = r.timestamp - motion.previousStamp;
    if (motion.hasPrevious && dt > 0)
      lastVelocity_ = (finalPose(rec).translation() - motion.previousPose.translation()) / dt;
    else
      lastVelocity_.reset();
    rec.state = last_ = r.quality.known && !r.quality.constrained ? TrackingState::weak : TrackingState::good;
    return;
  }
  if (rec.implausible.empty()) lastVelocity_.reset();
  if (motion.step && followOdometry(rec, motion)) {
    failedInARow_ = 0;
    rec.state = last_ = TrackingState::odometry;
    movedBy(rec, motion);
    return;
  }
  rec.state = last_ = TrackingState::lost;
  if (!rec.implausible.empty() && ++implausibleInARow_ < kMaxImplausibleInARow) {
    // The view matched the model elsewhere; the next frame tracks again from the extrapolated pose (a turn
    // before a bare wall, a spliced frame), until too many in a row say the tracker is not coming back.
    return;
  }
  implausibleInARow_ = 0;
  // With odometry whose budget is spent the pose is held from now on; without, after lost_after_failed_frames.
  if (++failedInARow_ >= config_.lostAfterFailedFrames || motion.step) {
    recovering_ = true;
    relocaliser_.reset();
    // From the next frame on the pose is held where this frame leaves it: no further extrapolation.
    d.nextStartPose.reset();
    d.correctedPose.reset();
  }
}

void TrackingMonitor::checkPhysics(Pipeline& pipeline, FrameRecord& rec, const FrameMotion& motion) {
  FrameResult& r = rec.result;
  const odometry::OdometryConfig& c = config_.odometry;
  const double dt = r.timestamp - motion.previousStamp;
  const std::string why =
      odometry::implausibleMotion(c, motion.previousPose, r.T_camera_to_world, dt, lastVelocity_);
  if (why.empty()) return;
  // The estimate catching up (the view agrees as well as before, within ICP's reach): it stands.
  const double excess =
      (r.T_camera_to_world.translation() - motion.previousPose.translation()).norm() - c.maxSpeedMPerS * dt;
  if (!agreement_.empty() && excess <= c.maxCorrectionM) {
    std::vector<double> recent(agreement_.begin(), agreement_.end());
    std::nth_element(recent.begin(), recent.begin() + recent.size() / 2, recent.end());
    if (r.pairAgreement >= recent[recent.size() / 2] - c.jumpAgreementMargin) return;
  }
  discardTrack(pipeline, rec, motion, why);
}

void TrackingMonitor::discardTrack(Pipeline& pipeline, FrameRecord& rec, const FrameMotion& motion,
                                   const std::string& why) {
  // Not a motion this platform makes: the view matched the model somewhere else (a runaway, a spliced frame).
  // Discarded like a failed track: the pose goes on at the last velocity (or follows the odometry), nothing
  // fused, and the next frame tracks from there; a run of them ends as failures (relocalisation).
  FrameResult& r = rec.result;
  const double dt = r.timestamp - motion.previousStamp;
  rec.implausible = why;
  pipeline.discardTrack(r);
  Decision& d = rec.decision;
  // The pose goes on at the last plausible velocity (held without one), the rotation held.
  Eigen::Isometry3d extrapolated = motion.previousPose;
  if (lastVelocity_ && dt > 0) extrapolated.translation() += *lastVelocity_ * dt;
  d.correctedPose = extrapolated;
  d.refinedPose.reset();
  d.integrate = false;
  d.keepReference = false;
  d.nextStartPose.reset();
}

void TrackingMonitor::fuse(FrameRecord& rec, const FrameMotion& motion) {
  const odometry::OdometryStep& step = *motion.step;
  Decision& d = rec.decision;
  const Eigen::Isometry3d predicted = motion.previousPose * step.delta;
  const Eigen::Isometry3d& tracked = d.refinedPose ? *d.refinedPose : rec.result.T_camera_to_world;
  const odometry::Fusion f =
      odometry::fuseWithOdometry(rec.result.quality, motion.previousPose, tracked, predicted, step, config_.odometry,
                                 motion.level);
  if (f.rejected) {
    rec.odometry.rejected = true;
    rec.odometry.why = f.why;
    return;
  }
  rec.odometry.used = true;
  if (motion.raw) calibration_.learn(rec.result.quality, motion.previousPose, tracked, *motion.raw);
  d.refinedPose = f.pose;
  d.correctedPose.reset();  // a controller's extrapolation gives way to the wheels' word
}

void TrackingMonitor::followWheels(FrameRecord& rec, const FrameMotion& motion) {
  if (last_ == TrackingState::odometry) {  // depth could not track: the dead reckoning and its budget go on
    if (followOdometry(rec, motion)) movedBy(rec, motion);
    return;
  }
  // Between two tracked frames the wheels carry the pose: one frame of a calibrated step is millimetres off.
  Decision& d = rec.decision;
  d.correctedPose = motion.previousPose * motion.step->delta;
  d.refinedPose.reset();
  d.integrate = false;
  d.keepReference = true;  // the next tracked frame pairs with the last raycast, as after any unfused frame
  d.nextStartPose.reset();
  rec.odometry.used = true;
  movedBy(rec, motion);
}

void TrackingMonitor::movedBy(const FrameRecord& rec, const FrameMotion& motion) {
  const double dt = rec.result.timestamp - motion.previousStamp;
  if (rec.decision.correctedPose && dt > 0)
    lastVelocity_ = (rec.decision.correctedPose->translation() - motion.previousPose.translation()) / dt;
}

bool TrackingMonitor::followOdometry(FrameRecord& rec, const FrameMotion& motion) {
  const odometry::OdometryConfig& c = config_.odometry;
  const odometry::OdometryStep& step = *motion.step;
  const Eigen::Isometry3d pose = odometryPose_.value_or(motion.previousPose) * step.delta;
  const double distance = odometryDistanceM_ + step.distanceM();
  const double time = odometryTimeS_ + step.dt;
  odometryPose_ = pose;
  odometryDistanceM_ = distance;
  odometryTimeS_ = time;
  rec.odometry.driftM = distance;
  if (distance > c.maxDistanceM || time > c.maxTimeS) {
    rec.odometry.why = format("odometry alone for %.2f m, %.1f s: beyond its bound (max_distance_m, max_time_s)",
                              distance, time);
    return false;
  }
  Decision& d = rec.decision;
  d.correctedPose = pose;
  d.refinedPose.reset();
  // A covered lens or a blank view: nothing fused. When the view is back but the model in it is too sparse to
  // track against (the volume moved on while the camera was blind, the region ahead was never mapped), the
  // frame is fused at the odometry's pose, within its drift bound: the map's weights keep what it held, the
  // holes fill, and the next frame tracks against it.
  rec.odometry.fused = rec.result.trackingAttempted && rec.result.inlierFraction > 0.0 && rec.implausible.empty();
  d.integrate = rec.odometry.fused;
  d.keepReference = false;
  d.nextStartPose.reset();
  rec.odometry.used = true;
  return true;
}

TrackAttempt TrackingMonitor::tryWithOdometry(const TrackAttempt& attempt) const {
  if (!odometryPose_ || !attempt.tracked) return attempt;
  const odometry::OdometryConfig& c = config_.odometry;
  const double tolerance = c.relocaliseToleranceM + c.noisePerM * odometryDistanceM_;
  if ((attempt.T_camera_to_world.translation() - odometryPose_->translation()).norm() <= tolerance) return attempt;
  TrackAttempt refused = attempt;  // the wheels say the camera is elsewhere: a repeating place, not this one
  refused.tracked = false;
  return refused;
}

void TrackingMonitor::relocalise(Pipeline& pipeline, const DepthFrame& frame, double depthScale, FrameRecord& rec,
                                 const FrameMotion& motion) {
  FrameResult& r = rec.result;
  Decision& d = rec.decision;
  rec.relocalising = true;
  rec.odometry.driftM = odometryDistanceM_;
  if (config_.relocalise) {
    Knobs knobs;  // DEFAULT's ICP (icp 1e-5, pd 10:5:4) at the relocaliser's compute size
    knobs.csr = config_.relocaliseCsr;
    const TryPose tryPose = [&](const Eigen::Isometry3d& start) {
      if (keptMapPrepare_ && !keptMapPrepare_(start)) {
        TrackAttempt skipped;  // not tried this frame: fails
        skipped.start = skipped.T_camera_to_world = start;
        return skipped;
      }
      return tryWithOdometry(pipeline.trackFrom(frame, depthScale, knobs, start, r));
    };
    const FernCode code = encoder_.encode(frame.depth, 1.0 / depthScale);
    // The odometry's dead-reckoned pose is the first candidate when there is one, else the held pose.
    rec.relocalisation = relocaliser_.relocalise(code, odometryPose_.value_or(pipeline.pose()), tryPose);
    if (keptMapPrepare_) keptMapVerdict(rec.relocalisation, motion);
  } else {
    rec.relocalisation.why = "relocalisation is off";
  }
  // The held pose, nothing fused, no correction; the next frame's ICP starts from this frame's final pose.
  d.correctedPose.reset();
  d.refinedPose.reset();
  d.integrate = false;
  d.keepReference = false;
  d.nextStartPose.reset();
  if (rec.relocalisation.accepted) {
    pipeline.adoptAttempt(*rec.relocalisation.attempt, r);
    recovering_ = false;
    failedInARow_ = 0;
    odometryPose_.reset();
    odometryDistanceM_ = odometryTimeS_ = 0.0;
    rec.state = last_ = TrackingState::relocalised;
    if (keptMapPrepare_) {  // localised in the kept map: from now on as without a store
      keptMapPrepare_ = nullptr;
      relocaliser_.setTryHeldPose(true);
      relocaliser_.setViewOffsets({});
      relocaliser_.setConfirmFrames(config_.relocaliseConfirmFrames);
      keptAnchor_.reset();
    }
  } else {
    r.tracked = false;
    rec.state = last_ = TrackingState::lost;
  }
}

void TrackingMonitor::keptMapVerdict(RelocaliseOutcome& out, const FrameMotion& motion) {
  if (out.confirmed == 0 || !out.attempt) {
    keptAnchor_.reset();
    return;
  }
  const Eigen::Isometry3d& pose = out.attempt->T_camera_to_world;
  if (out.confirmed == 1 || !keptAnchor_ || !motion.step) {  // a new candidate (or no wheels): its own anchor
    keptAnchor_ = pose;
    keptAnchorDistanceM_ = 0.0;
    return;
  }
  keptAnchor_ = *keptAnchor_ * motion.step->delta;
  keptAnchorDistanceM_ += motion.step->distanceM();
  const double off = (pose.translation() - keptAnchor_->translation()).norm();
  const double tolerance = kKeptMapOdometryToleranceM + config_.odometry.noisePerM * keptAnchorDistanceM_;
  if (off <= tolerance) return;
  out.why += format("; refused: the wheels put the camera %.3f m from it after %.2f m", off, keptAnchorDistanceM_);
  out.accepted = false;
  out.confirmed = 0;
  relocaliser_.reset();
  keptAnchor_.reset();
}

void TrackingMonitor::startInKeptMap(const std::vector<Keyframe>& keyframes, KeptMapPrepare prepare,
                                     const std::vector<double>& offsetsM) {
  relocaliser_.seed(keyframes);
  relocaliser_.setTryHeldPose(false);
  relocaliser_.setViewOffsets(offsetsM);
  relocaliser_.setConfirmFrames(std::max(config_.relocaliseConfirmFrames, kKeptMapConfirmFrames));
  keptMapPrepare_ = std::move(prepare);
  recovering_ = true;
  last_ = TrackingState::lost;
}

void TrackingMonitor::after(const DepthFrame& frame, double depthScale, FrameRecord& rec) {
  if (rec.state == TrackingState::good && rec.result.trackingAttempted && !rec.result.poseOverridden &&
      config_.relocalise) {
    const FernCode code = encoder_.encode(frame.depth, 1.0 / depthScale);
    rec.keyframeAdded = relocaliser_.harvest(code, rec.result.T_camera_to_world, rec.result.frame);
    relocaliser_.noteTracked(rec.result.pairAgreement);
  }
  rec.keyframes = relocaliser_.keyframes().size();
}

}  // namespace sb
