#include "runtime/tracking_monitor.h"

#include <algorithm>
#include <cstdio>

namespace sb {

TrackingMonitor::TrackingMonitor(const PipelineConfig& config)
    : config_(config), encoder_(FernParams{}), relocaliser_(RelocaliserParams(config)) {}

void TrackingMonitor::resolve(Pipeline& pipeline, const DepthFrame& frame, double depthScale, FrameRecord& rec,
                              odometry::MotionModel& model, const odometry::FrameMotion& motion) {
  FrameResult& r = rec.result;
  Decision& d = rec.decision;
  // The view's own prediction is tracked at the frame's knobs, with DEFAULT's ICP iterations at least.
  Knobs knobs = r.knobs;
  for (size_t level = 0; level < knobs.pyramidIterations.size(); ++level)
    knobs.pyramidIterations[level] = std::max(knobs.pyramidIterations[level], Knobs{}.pyramidIterations[level]);
  const odometry::FrameView view{r, d, rec.odometry, rec.implausible, [&](const Eigen::Isometry3d& start) {
                                   return pipeline.trackFrom(frame, depthScale, knobs, start, r);
                                 }};
  if (model.track()) model.depthSeen(frame.depth, depthScale, pipeline.intrinsics(), motion);
  if (!r.trackingAttempted && !recovering_) {  // bootstrap, or a frame skipped by the tracking rate
    rec.state = last_ == TrackingState::relocalised ? TrackingState::good : last_;
    // A frame the view has not checked for too long is the wheels' word alone.
    if (r.frame >= static_cast<size_t>(config_.bootstrapFrames) &&
        !model.skipped(view, motion, last_ == TrackingState::odometry))
      rec.state = TrackingState::odometry;
    return;
  }
  if (recovering_) {
    if (!localisingInKeptMap()) model.deadReckon(motion);  // the dead reckoning is in no frame of a kept map
    relocalise(pipeline, frame, depthScale, rec, model, motion);
    return;
  }
  model.judge(pipeline, view, motion);
  if (r.tracked) {
    implausibleInARow_ = 0;
    model.viewFixed(view, motion);
    if (!goodAgreement_) goodAgreement_.emplace(model.config().mapAgreementFraction);
    const double coverage = r.modelCoverage;
    if (goodAgreement_->contradicted(r.pairAgreement, coverage)) {
      // The view does not fit the map where it was tracked: a failed track that passed the residual and inlier
      // tests. Not good and not fused (fused, it would rewrite the map around the wrong pose until the view
      // agreed with it); lost_after_failed_frames of them in a row (failed tracks included) and the relocaliser
      // decides, whose bar a look-alike does not reach.
      rec.state = last_ = TrackingState::weak;
      d.integrate = false;
      d.keepReference = true;
      if (++failedInARow_ >= config_.lostAfterFailedFrames) {
        recovering_ = true;
        relocaliser_.reset();
        d.nextStartPose.reset();
        d.correctedPose.reset();
      }
      return;
    }
    failedInARow_ = 0;
    // While the wheels and the view dispute the motion the pose is the view's, but not yet `good`.
    const bool weak = (r.quality.known && !r.quality.constrained) || model.fault() == odometry::WheelFault::disputed;
    if (!weak) {
      goodAgreement_->add(r.pairAgreement);
      goodAgreement_->addCoverage(coverage);
    }
    rec.state = last_ = weak ? TrackingState::weak : TrackingState::good;
    return;
  }
  if (model.fault() == odometry::WheelFault::kidnapped) {
    // The view has not fitted the map near the wheels' pose for a while: the relocaliser searches the whole map.
    rec.state = last_ = TrackingState::lost;
    recovering_ = true;
    relocaliser_.reset();
    d.nextStartPose.reset();
    d.correctedPose.reset();
    return;
  }
  if (model.follow(view, motion)) {
    failedInARow_ = 0;
    rec.state = last_ = TrackingState::odometry;
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

void TrackingMonitor::relocalise(Pipeline& pipeline, const DepthFrame& frame, double depthScale, FrameRecord& rec,
                                 odometry::MotionModel& model, const odometry::FrameMotion& motion) {
  FrameResult& r = rec.result;
  Decision& d = rec.decision;
  rec.relocalising = true;
  rec.odometry.driftM = model.deadReckonedM();
  if (config_.relocalise) {
    Knobs knobs;  // DEFAULT's ICP (icp 1e-5, pd 10:5:4) at the relocaliser's compute size
    knobs.csr = config_.relocaliseCsr;
    const KeptMapPrepare& prepare = keptMapPrepare_ ? keptMapPrepare_ : recoveryPrepare_;
    relocaliser_.setRotateStarts(!keptMapPrepare_ && recoveryPrepare_);
    // In the run, a candidate the wheels refuse where it starts (not kidnapped, far from their dead reckoning) is
    // tried in the volume as it stands: moved for it, the volume would show a place the wheels refuse anyway.
    const auto refusedByWheels = [&](const Eigen::Isometry3d& start) {
      TrackAttempt probe;
      probe.tracked = true;
      probe.start = probe.T_camera_to_world = start;
      return !model.vet(probe).tracked;
    };
    const TryPose tryPose = [&](const Eigen::Isometry3d& start) {
      const bool place = keptMapPrepare_ || (recoveryPrepare_ && !refusedByWheels(start));
      if (place && !prepare(start)) {
        TrackAttempt skipped;  // not tried this frame: fails
        skipped.start = skipped.T_camera_to_world = start;
        return skipped;
      }
      return model.vet(pipeline.trackFrom(frame, depthScale, knobs, start, r));
    };
    const FernCode code = encoder_.encode(frame.depth, 1.0 / depthScale);
    if (keptMapPrepare_) {
      // The path check needs the wheels and pairs counted within the sensor's noise (both backends count them):
      // tracking's agreement alone refused the right building's earlier views (0.67 on the PoCL device, where the
      // noise gives 0.99), and without the check the relaxed confirmation below would take another building's end
      // wall; on a backend that does not count them the relocaliser's frames alone decide, as without wheels.
      const bool pathCheck = motion.step && pipeline.backend().countsPairsInNoise();
      keptHistory_.add(frame, pathCheck ? std::optional<Eigen::Isometry3d>(motion.step->delta) : std::nullopt);
      // Carried by the wheels, a candidate's confirming frames need tracking's conditioning only: the path behind
      // it is checked before it is accepted (keptMapVerdict), and a view nearing an end wall leaves the sideways
      // motion nearly free where the wheels hold it.
      relocaliser_.setConfirmConditioning(pathCheck ? std::optional<double>(config_.constrainedMinConditioning)
                                                    : std::nullopt);
    }
    // The odometry's dead-reckoned pose is the first candidate when there is one, else the held pose.
    rec.relocalisation = relocaliser_.relocalise(code, model.deadReckoned().value_or(pipeline.pose()), tryPose);
    if (keptMapPrepare_) {
      DepthNoiseModel noise = pipeline.sensorNoise();
      if (!noise.on()) noise.disparityNoisePx = kKeptMapPathDisparityNoisePx;
      const TryView tryView = [&](const DepthFrame& view, const Eigen::Isometry3d& start) {
        return pipeline.trackOtherFrom(view, depthScale, knobs, start, noise, r);
      };
      keptMapVerdict(rec.relocalisation, motion, model.config(), tryView);
    }
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
    model.relocalised();
    rec.state = last_ = TrackingState::relocalised;
    if (keptMapPrepare_) {  // localised in the kept map: from now on as without a store
      keptMapPrepare_ = nullptr;
      keptMapLocalised_ = true;
      relocaliser_.setTryHeldPose(true);
      relocaliser_.setViewOffsets(recoveryOffsetsM_);
      relocaliser_.setConfirmFrames(config_.relocaliseConfirmFrames);
      relocaliser_.setConfirmConditioning(std::nullopt);
      keptAnchor_.reset();
      keptHistory_.clear();
    }
  } else {
    r.tracked = false;
    rec.state = last_ = TrackingState::lost;
  }
}

void TrackingMonitor::keptMapVerdict(RelocaliseOutcome& out, const odometry::FrameMotion& motion,
                                     const odometry::OdometryConfig& odometry, const TryView& tryView) {
  if (out.confirmed == 0 || !out.attempt) {
    keptAnchor_.reset();
    return;
  }
  const Eigen::Isometry3d& pose = out.attempt->T_camera_to_world;
  if (out.confirmed == 1 || !keptAnchor_ || !motion.step) {  // a new candidate (or no wheels): its own anchor
    keptAnchor_ = pose;
    keptAnchorDistanceM_ = 0.0;
    if (out.confirmed == 1) keptConfirmRelaxed_ = keptPathShort_ = false;
  } else {
    keptAnchor_ = *keptAnchor_ * motion.step->delta;
    keptAnchorDistanceM_ += motion.step->distanceM();
    const double off = (pose.translation() - keptAnchor_->translation()).norm();
    const double tolerance = kKeptMapOdometryToleranceM + odometry.noisePerM * keptAnchorDistanceM_;
    if (off > tolerance) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "; refused: the wheels put the camera %.3f m from it after %.2f m", off,
                    keptAnchorDistanceM_);
      refuseKeptCandidate(out, buf);
      return;
    }
  }
  keptConfirmRelaxed_ =
      keptConfirmRelaxed_ || out.attempt->quality.conditioning < relocaliser_.params().minConditioning;
  // The path the wheels drove behind it (none without wheels: then the relocaliser's frames alone, at its own
  // conditioning, decide): judged when the candidate has held kKeptMapPathConfirmFrames frames over a path long
  // enough (once), and when the relocaliser would accept it.
  const bool wheels = motion.step.has_value() && keptHistory_.size() > 1;
  const bool judge = wheels && !keptPathShort_ && out.confirmed >= kKeptMapPathConfirmFrames &&
                     keptHistory_.pathM() >= kKeptMapPathMinM;
  if (!(judge || (out.accepted && (wheels || keptConfirmRelaxed_)))) return;
  const PathTest test{kKeptMapPathAgreement, odometry.noisePerM};
  const PathVerdict path = keptHistory_.check(pose, test, tryView);
  if (path.refused()) {
    refuseKeptCandidate(out, "; refused: an earlier view does not fit the kept surface where the wheels put it: " +
                                 path.why);
  } else if (path.pathM >= kKeptMapPathMinM) {
    out.why += "; accepted: the path behind it fits: " + path.why;
    out.accepted = true;
    relocaliser_.reset();
  } else if (!out.accepted) {
    keptPathShort_ = true;  // too little of it covered yet: confirmed on, judged again when it would be accepted
  } else if (keptConfirmRelaxed_) {
    refuseKeptCandidate(out, "; refused: confirmed at tracking's conditioning, and too little of the path behind it "
                             "is covered by the kept surface to vouch for it: " + path.why);
  } else {  // a robot that has hardly moved: the relocaliser's frames at its own conditioning, as without wheels
    out.why += "; the path behind it is short (" + path.why + ")";
  }
}

void TrackingMonitor::refuseKeptCandidate(RelocaliseOutcome& out, const std::string& why) {
  out.why += why;
  out.accepted = false;
  out.confirmed = 0;
  relocaliser_.reset();
  keptAnchor_.reset();
  keptConfirmRelaxed_ = keptPathShort_ = false;
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

void TrackingMonitor::setRecoveryPrepare(KeptMapPrepare prepare, const std::vector<double>& offsetsM) {
  recoveryPrepare_ = std::move(prepare);
  recoveryOffsetsM_ = offsetsM;
  if (!keptMapPrepare_) relocaliser_.setViewOffsets(offsetsM);
}

void TrackingMonitor::after(const DepthFrame& frame, double depthScale, FrameRecord& rec) {
  if (rec.state == TrackingState::good && rec.result.trackingAttempted && !rec.result.poseOverridden &&
      config_.relocalise) {
    const FernCode code = encoder_.encode(frame.depth, 1.0 / depthScale);
    rec.keyframeAdded = relocaliser_.harvest(code, rec.result.T_camera_to_world, rec.result.frame);
    relocaliser_.noteTracked(rec.result.pairAgreement);
  }
  rec.keyframes = relocaliser_.keyframes().size();
  rec.keptMap = localisingInKeptMap() ? KeptMap::localising : keptMapLocalised_ ? KeptMap::localised : KeptMap::none;
}

}  // namespace sb
