#include "runtime/slam_runner.h"

#include <chrono>

#include "core/error.h"
#include "power/clock.h"

namespace sb {

SlamRunner::SlamRunner(Pipeline& pipeline, std::unique_ptr<Controller> controller, double depthScale)
    : pipeline_(pipeline), depthScale_(depthScale), previousPose_(pipeline.pose()) {
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
}

void SlamRunner::pinKnobs(const std::optional<Knobs>& knobs) {
  if (knobs) validateKnobs(*knobs);
  pinned_ = knobs;
}

FrameRecord SlamRunner::step(const DepthFrame& frame) {
  FrameRecord rec;
  rec.startMonoNs = power::monotonicClock().nowNs();
  rec.knobsPinned = pinned_.has_value();
  rec.result = pipeline_.trackFrame(frame, depthScale_, nextKnobs());
  const FrameResult& r = rec.result;

  Observation obs;
  obs.frame = r.frame;
  obs.timestamp = r.timestamp;
  obs.knobs = r.knobs;
  obs.trackingAttempted = r.trackingAttempted;
  obs.tracked = r.tracked;
  obs.pose = r.T_camera_to_world;
  obs.previousPose = previousPose_;
  obs.velocity = (r.T_camera_to_world.translation() - previousPose_.translation()).norm();
  obs.residual = r.residual;
  obs.inlierFraction = r.inlierFraction;
  obs.times = r.times;
  obs.previousComputationMs = previousComputationMs_;
  obs.latestJoules = latestJoules_;
  obs.depth = &frame.depth;
  obs.depthScale = depthScale_;
  rec.trackedVelocity = obs.velocity;

  const auto start = std::chrono::steady_clock::now();
  rec.decision = controller_->decide(obs);
  rec.controllerMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  rec.controller = controller_->name();
  try {
    validateKnobs(rec.decision.next);
  } catch (const Error& e) {
    throw Error("controller '" + controller_->name() + "' chose invalid knobs at frame " + std::to_string(r.frame) +
                ": " + e.what());
  }

  pipeline_.finishFrame(rec.result, rec.decision.correctedPose);
  next_ = rec.decision.next;
  if (pinned_) rec.decision.next = *pinned_;
  previousPose_ = rec.result.T_camera_to_world;
  previousComputationMs_ = rec.result.times.computationMs();
  ++frames_;
  rec.endMonoNs = power::monotonicClock().nowNs();
  for (auto& sink : sinks_) sink->onFrame(rec);
  return rec;
}

void SlamRunner::flush() {
  for (auto& sink : sinks_) sink->flush();
}

}  // namespace sb
