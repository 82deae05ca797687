#pragma once
// What the runtime records about one processed frame: the pipeline's result, the controller's decision and
// the controller's own cost. Output sinks receive it; the daemon publishes it.

#include <cstdint>
#include <optional>
#include <string>

#include "controller/controller.h"
#include "pipeline/pipeline.h"
#include "odometry/motion_model.h"
#include "reloc/relocaliser.h"
#include "core/tracking_state.h"

namespace sb {

using odometry::FrameOdometry;  // odometry/motion_model.h

// A run started with a kept map (runtime/map_store.h): still localising in it (no pose in its frame yet), or
// localised (the pose is in the store's frame, the frame of the run that made it). `none`: no kept map (a run
// without a store, or one writing a new store).
enum class KeptMap { none, localising, localised };
inline const char* keptMapName(KeptMap k) {
  return k == KeptMap::localising ? "localising" : k == KeptMap::localised ? "localised" : "none";
}

struct FrameRecord {
  FrameResult result;             // after finishFrame: final pose, stage times, velocity of the final pose
  Decision decision;              // the controller's decision after this frame (decision.next = next knobs)
  std::string controller;         // name of the controller that decided
  bool knobsPinned = false;       // decision.next was overridden by pinned knobs
  double trackedVelocity = 0.0;   // m/frame: velocity of the tracked pose, before any correction
  double controllerMs = 0.0;      // time spent in Controller::decide (and reading the frame for it)
  // Half precision of this frame: what the previous decision wished (or the config forced), whether the
  // backend has it at all, and what it ran with (the CPU backend has no half path: never applied).
  bool halfRequested = false, halfSupported = false, halfApplied = false;
  // CLOCK_MONOTONIC (ns) when the runner began the frame (frame in hand, before preprocessing) and finished it
  // (after integration/raycast and the controller, before the outputs): the interval the power meter's
  // ledger charges to this frame (power/power_sampler.h).
  // Tracking state (runtime/tracking_monitor.h): of this frame; whether the relocaliser ran on it and what it
  // found; whether the frame became a keyframe, and the keyframes held after it.
  TrackingState state = TrackingState::good;
  bool relocalising = false;
  RelocaliseOutcome relocalisation;
  bool keyframeAdded = false;
  size_t keyframes = 0;
  KeptMap keptMap = KeptMap::none;  // frames.jsonl / POSE "kept_map" (absent when none)
  // The frame's pose is an estimate: the frame was not lost. A lost frame's pose is the last good one, held, or
  // the controller's extrapolation of it: not a measurement. trajectory.tum and the ATE leave lost frames out
  // (the TUM convention: a trajectory lists the frames the system estimated; the tracked share and the lost
  // frames are in summary.json); the POSE message still carries them, marked lost, so a client knows.
  bool hasPoseEstimate() const { return sb::hasPoseEstimate(state); }
  FrameOdometry odometry;
  // The frame's motion is one the platform cannot make (docs/odometry.md): it is not `good`. Why, or empty.
  std::string implausible;
  int64_t startMonoNs = 0;
  int64_t endMonoNs = 0;
};

}  // namespace sb
