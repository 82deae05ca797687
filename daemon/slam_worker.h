#pragma once
// The SLAM thread: pinned to the configured CPUs, it owns the compute pool and one run per pass
// (runtime/run.h: pipeline, controller, outputs, energy), takes frames from the FrameQueue, and publishes one
// immutable FrameReport per frame through a callback that must not block (the daemon posts it to the event
// loop).
//
// Other threads talk to it only through the thread-safe methods below; it applies controller switches and
// pins between frames. Stopping: requestStop() and abort the queue; the thread finishes the frame in hand,
// flushes every output and exits.

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "controller/registry.h"
#include "core/segment_store.h"
#include "daemon/daemon_config.h"
#include "daemon/frame_queue.h"
#include "daemon/map_publisher.h"
#include "daemon/protocol.h"
#include "pipeline/config.h"
#include "power/power_sampler.h"
#include "runtime/knob_pins.h"
#include "odometry/odometry_input.h"
#include "runtime/slam_runner.h"

namespace sb::daemon {

struct WorkerStats {
  std::string state = "starting";  // starting, running, finished, failed
  std::string error;               // when failed
  uint64_t frames = 0;             // frames processed (all passes)
  uint64_t tracked = 0;
  // Tracking state (core/tracking_state.h), all passes: of the last frame, frames lost, times the tracker
  // was lost (stretches of lost frames) and times it relocalised.
  std::string trackingState = "good";
  uint64_t lostFrames = 0, lostStretches = 0, relocalisations = 0;
  // A pass started with a kept map (output.map_store, docs/map-store.md): "localising" or "localised", as the
  // last frame's POSE says; empty otherwise (no store, or a pass that makes a new one).
  std::string keptMap;
  // The robot's odometry (docs/odometry.md), all passes: frames that had it, frames that did not (in a run with
  // odometry), steps rejected as slips, frames posed by it alone; why the last frame had none.
  uint64_t odometryFrames = 0, odometryMissing = 0, odometryRejected = 0, odometryOnlyFrames = 0;
  std::string odometryWhy;
  uint32_t pass = 0;
  double fps = 0.0;            // over the last second or so of frames
  double computationMs = 0.0;  // mean over the run
  std::string controller;
  nlohmann::json pinned = nlohmann::json::object();
  std::string cpus;                                                // CPUs the thread is pinned to
  unsigned threads = 0;                                            // compute threads
  std::string outputDir;                                           // of the current pass
  std::optional<std::chrono::steady_clock::time_point> busySince;  // start of the frame in hand
};

// The controller settings of `slam` (slam.controller, or the file slam.controller_config whose own "name"
// wins; the file holds the settings object, bare or as config/controller.json's "controller" key).
// Validated; throws sb::Error naming the file or key.
ControllerSettings loadControllerSettings(const SlamConfig& slam, const ControllerContext& context);

// The pipeline config of a run of `sequence`: its volume size and start position, then the file
// slam.pipeline_config on top. Validated; throws sb::Error naming the file or key.
PipelineConfig buildPipelineConfig(const SlamConfig& slam, const SequenceInfo& sequence);
// The platform's physics and the odometry's noise: the "odometry" section of slam.pipeline_config (defaults
// without one). Throws sb::Error naming the file and key.
odometry::OdometryConfig buildOdometryConfig(const SlamConfig& slam);

class SlamWorker {
 public:
  using Publish = std::function<void(FrameReport)>;  // called on the SLAM thread; must not block
  using Finished = std::function<void()>;            // called on the SLAM thread as it exits
  using EnergyPublish = std::function<void(const power::FrameEnergy&)>;

  // Validates the pipeline config (file + sequence hints) and the controller settings. Throws sb::Error.
  SlamWorker(const DaemonConfig& config, const SequenceInfo& sequence, FrameQueue& queue, Publish publish,
             Finished finished);
  ~SlamWorker();  // joins
  SlamWorker(const SlamWorker&) = delete;
  SlamWorker& operator=(const SlamWorker&) = delete;

  // Before start(): account every frame's energy with `sampler` (owned by the caller, started, outliving the
  // worker; one runtime/EnergyAccount across passes): each pass's Run logs the results to its energy.jsonl and
  // passes known joules to the controller and to `publish` (called on the SLAM thread; must not block). At the
  // end the worker stops the sampler.
  void setPower(power::PowerSampler* sampler, EnergyPublish publish);
  // Before start(): rotate every pass's per-frame outputs into `segments` (shared with the daemon, which
  // reports its usage in STATUS); nullptr (the default): one file each.
  void setSegments(std::shared_ptr<SegmentStore> segments) { segments_ = std::move(segments); }
  // Before start(), with source.at_end "loop": the retention that each ended pass's directory joins
  // (daemon/pass_directories.h), so that the passes of a replay looping for weeks never fill the disk.
  void setPassRetention(std::shared_ptr<SegmentStore> retention) { passRetention_ = std::move(retention); }
  // Before start(), with output.navmap: the grid every output.navmap_period_s (daemon/map_publisher.h).
  void setMapPublish(MapPublisher::Publish publish) {
    if (maps_) maps_->setPublish(std::move(publish));
  }

  // Before start(): every pass's runner reads this odometry (odometry/odometry_input.h; its track may be the
  // live one the socket adds to), and its summary says so. Default: none.
  void setOdometry(OdometryInput odometry) { odometry_ = std::move(odometry); }

  void start();
  void requestStop() { stop_ = true; }
  void join();

  // Any thread. Switches the controller from the next frame on; `settings` already validated.
  void switchController(const ControllerSettings& settings, const std::string& name);
  // Any thread. Applies pin/unpin changes to a copy and installs it; throws sb::Error (nothing changes).
  nlohmann::json changePins(const ControlRequest& request);
  const ControllerContext& controllerContext() const { return context_; }
  // Any thread. The controller settings in force (read at construction, replaced by switchController): the
  // daemon's one copy, whose sections ?CONTROL's switches use.
  ControllerSettings controllerSettings() const;
  WorkerStats stats() const;

 private:
  struct Passes;  // the state of runPasses (slam_worker.cpp)
  void run();
  void runPasses();
  // A new pass: ends the pass in hand, opens the next one's directory and Run with the controller in force.
  void startPass(Passes& p);
  // Ends the pass in hand (its end-of-run outputs); `last`: waits for the energy of its last frames.
  void finishPass(Passes& p, bool last, const std::string& error = {});
  // Before a frame: a controller switched or pins changed since the last one reach the runner. Returns the
  // names of the pinned knobs.
  std::vector<std::string> applyChanges(SlamRunner& runner);
  // After a frame: the counts of STATUS; flushes the outputs every kFlushInterval.
  void countFrame(Passes& p, const FrameRecord& record);

  DaemonConfig config_;
  SequenceInfo sequence_;
  PipelineConfig pipelineConfig_;
  odometry::OdometryConfig odometryConfig_;
  ControllerContext context_;
  FrameQueue& queue_;
  Publish publish_;
  Finished finished_;
  power::PowerSampler* sampler_ = nullptr;
  EnergyPublish publishEnergy_;
  std::shared_ptr<SegmentStore> segments_;
  std::shared_ptr<SegmentStore> passRetention_;
  OdometryInput odometry_;
  std::unique_ptr<MapPublisher> maps_;  // output.navmap
  std::atomic<bool> stop_{false};
  std::thread thread_;

  mutable std::mutex mutex_;  // guards everything below
  ControllerSettings settings_;    // in force: settings_.name is the controller of the next frame and pass
  bool controllerChanged_ = false;  // switched since the last frame: the runner gets a new controller
  KnobPins pins_;
  bool pinsChanged_ = false;
  WorkerStats stats_;
};

}  // namespace sb::daemon
