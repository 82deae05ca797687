#include "runtime/slam_runner.h"

#include <chrono>

#include "core/error.h"
#include "power/clock.h"

namespace sb {

SlamRunner::SlamRunner(Pipeline& pipeline, std::unique_ptr<Controller> controller, double depthScale,
                       const odometry::OdometryConfig& motion)
    : pipeline_(pipeline),
      depthScale_(depthScale),
      previousPose_(pipeline.pose()),
      monitor_(pipeline.config()),
      motion_(motion) {
  setController(std::move(controller));
}

OutputSink& SlamRunner::addSink(std::unique_ptr<OutputSink> sink) {
  if (!sink) throw Error("SlamRunner::addSink: no sink given");
  sinks_.push_back(std::move(sink));
  return *sinks_.back();
}

void SlamRunner::setController(std::unique_ptr<Controller> controller) {
  if (!controller) throw Error("SlamRunner: no controller given");
  const Knobs initial = controller->initialKnobs();
  try {
    validateKnobs(initial);
  } catch (const Error& e) {
    throw Error("controller '" + controller->name() + "' starts with invalid knobs: " + e.what());
  }
  controller_ = std::move(controller);
  next_ = initial;
  nextStart_ = IcpStart{};
  nextHalf_ = false;
}

void SlamRunner::applyHalfPrecision(FrameRecord& rec) {
  // The config's opencl_half_storage forces half for the whole run; a controller's wish adds to it.
  ComputeBackend& backend = pipeline_.backend();
  rec.halfRequested = nextHalf_ || pipeline_.config().openclHalfStorage;
  rec.halfSupported = backend.supportsHalfPrecision();
  if (rec.halfSupported && backend.halfPrecision() != rec.halfRequested) backend.setHalfPrecision(rec.halfRequested);
  rec.halfApplied = backend.halfPrecision();
}

Observation SlamRunner::observe(const FrameResult& r, const DepthFrame& frame,
                                const odometry::FrameMotion& motion) const {
  Observation obs;
  obs.odometry = motion.step.has_value();
  obs.frame = r.frame;
  obs.timestamp = r.timestamp;
  obs.knobs = r.knobs;
  obs.trackingAttempted = r.trackingAttempted;
  obs.tracked = r.tracked;
  obs.pose = r.T_camera_to_world;
  obs.previousPose = previousPose_;
  obs.velocity = (r.T_camera_to_world.translation() - previousPose_.translation()).norm();
  obs.rotationDeg = Eigen::AngleAxisd(previousPose_.linear().transpose() * r.T_camera_to_world.linear()).angle() *
                    180.0 / 3.141592653589793;
  obs.residual = r.residual;
  obs.inlierFraction = r.inlierFraction;
  obs.icpLevelIterations = r.icpLevelIterations;
  obs.icpUpdateNorm = r.icpUpdateNorm;
  obs.quality = r.quality;
  obs.retracked = r.retracked;
  obs.firstKnobs = r.firstKnobs;
  obs.times = r.times;
  obs.previousComputationMs = previousComputationMs_;
  obs.latestJoules = latestJoules_;
  obs.depth = &frame.depth;
  obs.depthScale = depthScale_;
  return obs;
}

Decision SlamRunner::decide(const Observation& obs, FrameRecord& rec) {
  const auto start = std::chrono::steady_clock::now();
  Decision d = controller_->decide(obs);
  rec.controllerMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  for (const Knobs* k : {&d.next, d.retrack ? &*d.retrack : nullptr}) {
    if (!k) continue;
    try {
      validateKnobs(*k);
    } catch (const Error& e) {
      throw Error("controller '" + controller_->name() + "' chose invalid knobs at frame " + std::to_string(obs.frame) +
                  ": " + e.what());
    }
  }
  return d;
}

FrameRecord SlamRunner::step(const DepthFrame& frame) {
  FrameRecord rec;
  rec.startMonoNs = power::monotonicClock().nowNs();
  rec.knobsPinned = !pins_.empty();
  applyHalfPrecision(rec);
  const odometry::FrameMotion motion =
      motion_.predict(previousPose_, previousStamp_, frames_ > 0, frame.timestamp, rec.odometry);
  IcpStart start = nextStart_;
  if (motion.step) start.pose = motion.predicted();  // ICP starts from the odometry's motion
  start.prior = motion.prior;
  Knobs knobs = nextKnobs();
  if (motion_.needsView()) knobs.trackingRate = 1;  // the view last checked the wheels too long ago
  rec.result = pipeline_.trackFrame(frame, depthScale_, knobs, start);
  // Lost for a while: a plain track is not trusted (the relocaliser decides, in resolve()).
  if (monitor_.recovering()) pipeline_.discardTrack(rec.result);
  Observation obs = observe(rec.result, frame, motion);
  rec.decision = decide(obs, rec);
  // A controller may have the frame tracked once more (at other knobs) before it is finished; pinned knobs
  // are never replaced.
  if (rec.decision.retrack && pins_.empty()) {
    pipeline_.retrackFrame(frame, depthScale_, *rec.decision.retrack, rec.result);
    if (monitor_.recovering()) pipeline_.discardTrack(rec.result);
    obs = observe(rec.result, frame, motion);
    const uint32_t firstTriggers = rec.decision.triggers;
    rec.decision = decide(obs, rec);
    rec.decision.retrack.reset();
    rec.decision.triggers |= firstTriggers | kTriggerRetrack;
  }
  rec.trackedVelocity = obs.velocity;
  rec.controller = controller_->name();
  monitor_.resolve(pipeline_, frame, depthScale_, rec, motion_, motion);
  const FrameResult& r = rec.result;
  FrameOverrides overrides;  // by name: a member added to FrameOverrides shifts none into another's place
  overrides.integrate = rec.decision.integrate;
  overrides.keepReference = rec.decision.keepReference;
  overrides.refinedPose = rec.decision.refinedPose;
  overrides.integrateUntracked = rec.odometry.fused;
  overrides.referenceCsr = rec.decision.referenceCsr;
  pipeline_.finishFrame(rec.result, rec.decision.correctedPose, overrides);
  monitor_.after(frame, depthScale_, rec);
  next_ = rec.decision.next;
  nextStart_ = IcpStart{rec.decision.nextStartPose, rec.decision.nextHoldBelowConditioning};
  nextHalf_ = rec.decision.halfPrecision;
  rec.decision.next = nextKnobs();  // the controller's choice with the pins in place
  previousPose_ = r.T_camera_to_world;
  previousStamp_ = r.timestamp;
  const bool viewFixed =
      r.tracked && !r.poseOverridden && rec.state != TrackingState::odometry && rec.state != TrackingState::lost;
  motion_.finished(r.T_camera_to_world, r.timestamp, viewFixed, rec.odometry);
  previousComputationMs_ = r.times.computationMs();
  ++frames_;
  rec.endMonoNs = power::monotonicClock().nowNs();
  for (auto& sink : sinks_) sink->onFrame(rec);
  return rec;
}

void SlamRunner::flush() {
  for (auto& sink : sinks_) sink->flush();
}

}  // namespace sb
