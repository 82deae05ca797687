#pragma once
// The per-frame loop shared by `slambooster run`, `slambooster bench` and the daemon's SLAM thread:
//   frame -> Pipeline::trackFrame -> Controller::decide -> Pipeline::finishFrame(result, corrected pose)
//         -> every output sink
// One frame per step(), so the caller owns pacing, threads and stopping. Between any two steps the caller
// may switch the controller, pin knobs (overriding the controller's choice), report energy, or flush the
// outputs. Not thread-safe: one thread drives a runner.

#include <memory>
#include <optional>
#include <vector>

#include "controller/controller.h"
#include "drivers/frame_source.h"
#include "odometry/motion_model.h"
#include "pipeline/pipeline.h"
#include "runtime/frame_record.h"
#include "runtime/knob_pins.h"
#include "runtime/output_sink.h"
#include "runtime/tracking_monitor.h"

namespace sb {

class SlamRunner {
 public:
  // Borrows `pipeline` (must outlive the runner); owns `controller`. `depthScale`: raw units per metre.
  // `motion`: the platform's physics and the odometry's noise (the settings file's "odometry" section).
  SlamRunner(Pipeline& pipeline, std::unique_ptr<Controller> controller, double depthScale,
             const odometry::OdometryConfig& motion = {});

  // Adds an output; the runner owns it. Returns it for the caller's later use (e.g. reading a summary).
  OutputSink& addSink(std::unique_ptr<OutputSink> sink);

  // Processes one frame with the current knobs and returns its record (also given to every sink).
  // Throws sb::Error on bad input or invalid knobs from the controller (naming it).
  FrameRecord step(const DepthFrame& frame);

  // Replaces the controller from the next frame on; the next frame runs the new controller's initial knobs
  // (unless knobs are pinned).
  void setController(std::unique_ptr<Controller> controller);
  // Pins knobs over the controller's choice from the next frame on: each frame runs the controller's knobs
  // with `pins` in place (a partial set; empty: the controller's own). The controller still observes every
  // frame and may still correct poses; no re-track while any knob is pinned.
  void setPins(const KnobPins& pins) { pins_ = pins; }
  // Pins every knob (validated; throws sb::Error), or unpins all with nullopt.
  void pinKnobs(const std::optional<Knobs>& knobs) { pins_ = knobs ? KnobPins::all(*knobs) : KnobPins{}; }
  // Energy of the most recent frame whose energy is known (J), passed to the controller from now on.
  void setLatestJoules(double joules) { latestJoules_ = joules; }
  // The robot's odometry (odometry/odometry_track.h), shared with whoever adds samples (the daemon's socket);
  // nullptr: none. Read at each frame's stamp from the next frame on.
  void setOdometry(std::shared_ptr<const odometry::OdometryTrack> track) { motion_.setTrack(std::move(track)); }
  const odometry::OdometryTrack* odometry() const { return motion_.track(); }
  // Flushes every sink (files on disk reflect every frame so far).
  void flush();

  const Controller& controller() const { return *controller_; }
  // The knobs the next frame will run with.
  Knobs nextKnobs() const { return pins_.apply(next_); }
  const KnobPins& pins() const { return pins_; }
  size_t frames() const { return frames_; }
  const TrackingMonitor& monitor() const { return monitor_; }
  const odometry::MotionModel& motion() const { return motion_; }
  odometry::MotionModel& motion() { return motion_; }
  TrackingMonitor& monitor() { return monitor_; }  // a kept map's start (TrackingMonitor::startInKeptMap)
  Pipeline& pipeline() { return pipeline_; }

 private:
  // Switches the backend's half precision to what the last decision wished (where the backend has it).
  void applyHalfPrecision(FrameRecord& rec);
  Observation observe(const FrameResult& result, const DepthFrame& frame, const odometry::FrameMotion& motion) const;
  // Controller::decide, timed into rec.controllerMs, its knobs validated (throws sb::Error naming it).
  Decision decide(const Observation& observation, FrameRecord& rec);

  Pipeline& pipeline_;
  std::unique_ptr<Controller> controller_;
  double depthScale_;
  std::vector<std::unique_ptr<OutputSink>> sinks_;
  Knobs next_;
  KnobPins pins_;
  IcpStart nextStart_;  // the controller's ICP start for the next frame
  bool nextHalf_ = false;                        // the controller's half-precision wish for the next frame
  std::optional<double> latestJoules_;
  Eigen::Isometry3d previousPose_;
  double previousStamp_ = 0.0;
  double previousComputationMs_ = 0.0;
  size_t frames_ = 0;
  TrackingMonitor monitor_;
  odometry::MotionModel motion_;
};

}  // namespace sb
