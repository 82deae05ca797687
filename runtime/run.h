#pragma once
// One run (issue 22): a pipeline and its controller runner, the standard outputs of one directory
// (trajectory.tum, frames.jsonl, summary.json), the energy of its frames (energy.jsonl) and the end-of-run
// outputs (model.png, mesh.ply, report.html). `slambooster run` is one Run, and with it every bench, dse and
// profile run (they start `slambooster run`); every pass of the daemon is one.
//
//   RunOutputs outputs;                // every field by name; those not set keep their defaults
//   outputs.dir = dir;  outputs.groundTruthPath = groundTruth;  outputs.summary = summary;
//   outputs.comment = comment;  outputs.mapSlabs = true;
//   Run run(Pipeline::create(config, intrinsics, pool), createController(settings, context), depthScale,
//           outputs, account);   // account: borrowed, may be null
//   while (auto frame = source.next()) run.step(*frame);
//   run.finish(RunEnd{}, pool);  run.writeReport();
//
// Frames and energy go one way: step() hands the frame's interval to the energy account, writes the frames
// whose energy is now known to energy.jsonl, gives the newest to the controller and to the energy listener.
// Not thread-safe: one thread drives a run.

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/rotating_file.h"
#include "core/thread_pool.h"
#include "runtime/energy_account.h"
#include "runtime/map_sink.h"
#include "runtime/map_slabs.h"
#include "odometry/odometry_input.h"
#include "runtime/map_store.h"
#include "runtime/slam_runner.h"
#include "runtime/standard_outputs.h"

namespace sb {

// Where and what a run writes at its start. Set by name (the example above), not by position.
struct RunOutputs {
  std::string dir;              // created when missing
  std::string groundTruthPath;  // "" = no ATE in the summary
  RunSummary summary;           // what ran: starts summary.json (runtime/run_setup.h fills it)
  std::string comment;          // heads trajectory.tum
  // Rotation and retention of the per-frame outputs (trajectory, frame log, energy log;
  // core/rotating_file.h), shared by the runs of one output directory; nullptr: one file each (replays).
  std::shared_ptr<SegmentStore> segments;
  // With a moving volume: mesh every slab that leaves into DIR/map_slabs/ as it leaves (runtime/map_slabs.h,
  // on a worker thread), for mesh.ply at the end (RunEnd::mesh). false: the slabs are dropped.
  bool mapSlabs = false;
  // The slab files of DIR/map_slabs together at most this (bytes), the oldest removed first; 0: no limit (the
  // daemon's output.rotation.keep_slabs_mib).
  uint64_t keepSlabBytes = 0;
  // The daemon's retention store (rotation, or a looping replay's pass directories), or nullptr: with it the
  // slab files give way to its free-space floor and to a full disk (MapSlabsOptions::store).
  std::shared_ptr<SegmentStore> slabRetention;
  // The navigation map (issue 45; navmap/nav_map_sink.h), or nullptr: given every frame and every slab that
  // leaves, written into DIR at the end (map.pgm, map.yaml, map.bt) and by the daemon at its period.
  std::shared_ptr<MapSink> mapSink;
  // The map kept across runs (issue 55; runtime/map_store.h): its directory (created when absent, continued
  // when present: the run localises in it first), or "" for none. Needs a moving volume. None: a run with a
  // moving volume and relocalisation keeps its slabs in memory (relocalise_kept_map_mib) for its own
  // relocalisation.
  std::string mapStore;
  MapStoreOptions mapStoreOptions;
};

// What a run writes at its end.
struct RunEnd {
  std::string modelView = "last";  // model.png from the "last" camera pose or an "overview"; "" = none
  bool mesh = false;               // mesh.ply (marching cubes of the volume; with a moving volume, the map)
  bool drainEnergy = true;         // wait for the energy of the last frames (false: they land in a later run)
  bool complete = true;            // summary.json "complete" once every output is on disk
  std::string error;               // why the run ended early (e.g. the input failed): "error", not complete
};

class Run {
 public:
  // Owns `pipeline` and `controller`; borrows `energy` (nullptr: no energy accounting; must outlive the run).
  // `motion`: the platform's physics and the odometry's noise (odometry/odometry_config.h).
  // Creates the output directory and files (throws sb::Error naming them).
  Run(std::unique_ptr<Pipeline> pipeline, std::unique_ptr<Controller> controller, double depthScale,
      const odometry::OdometryConfig& motion, const RunOutputs& outputs, EnergyAccount* energy = nullptr);

  // One frame (SlamRunner::step), then its energy. Throws sb::Error on bad input or a failed write.
  FrameRecord step(const DepthFrame& frame);
  // Called for every frame energy the run resolves (known or not), on the thread that drives the run.
  void setEnergyListener(std::function<void(const power::FrameEnergy&)> listener) { listener_ = std::move(listener); }

  // Every output on disk reflects every frame so far (the energy totals too).
  void flush();
  // The end of the run: energy totals, every slab of the map written (the worker drained), model.png,
  // mesh.ply, then trajectory and frame log synced to disk and summary.json marked complete last (a run
  // killed at any point never leaves a complete summary beside a half-written trajectory). Throws sb::Error
  // naming a file that cannot be written.
  void finish(const RunEnd& end, ThreadPool& pool);
  // report.html from the outputs on disk; returns its path. Throws sb::Error when it cannot be written.
  std::string writeReport() const;

  SlamRunner& runner() { return runner_; }
  Pipeline& pipeline() { return *pipeline_; }
  SummarySink& summary() { return *outputs_.summary; }
  MapSink* mapSink() { return mapSink_.get(); }
  MapStore* mapStore() { return mapStore_.get(); }
  const std::string& dir() const { return dir_; }

 private:
  void record(const std::vector<power::FrameEnergy>& results);
  void startMapStore(const RunOutputs& outputs);  // in the constructor
  void stepMapStore(const FrameRecord& rec);      // after each frame
  void restoreStoreState();                       // a kept store's navmap.bin and odometry.bin, at the start
  void keepStoreState(bool final);                // navmap.bin and odometry.bin into the store
  void decideKeptMount(const Eigen::Vector3d& up);  // at the first frame the odometry gives a pose

  std::unique_ptr<Pipeline> pipeline_;
  SlamRunner runner_;
  std::string dir_;
  StandardOutputs outputs_;
  EnergyAccount* energy_ = nullptr;
  std::unique_ptr<RotatingFile> energyLog_;  // energy.jsonl, with an energy account
  std::function<void(const power::FrameEnergy&)> listener_;
  std::unique_ptr<MapSlabs> mapSlabs_;  // RunOutputs::mapSlabs with a moving volume
  std::optional<Eigen::Isometry3d> lastOdometryPose_;  // of the last frame the odometry covered
  std::shared_ptr<MapSink> mapSink_;    // RunOutputs::mapSink
  std::unique_ptr<MapStore> mapStore_;  // RunOutputs::mapStore
  size_t keyframesSavedAt_ = 0;         // the frame keyframes.bin was last written at
  size_t stateSavedAt_ = 0;             // the frame navmap.bin and odometry.bin were last written at
  bool recoveringOverStore_ = false;    // lost in the run: the volume kept, the window held (stepMapStore)
  bool keyframesDirty_ = false;
  // The mount's correction kept in the store, restored at the first frame the odometry gives a pose when the mount
  // the odometry assumes is the one it was learnt against (decideKeptMount); until then pending.
  struct KeptMount {
    odometry::MountCalibration::State state;
    std::optional<Eigen::Vector3d> up;  // KeptOdometry::mountUp
    std::string path;
  };
  std::optional<KeptMount> keptMount_;
  Eigen::Vector3d mountUpSum_ = Eigen::Vector3d::Zero();  // the odometry's up in the camera frame, over the frames
};

// The "overview" viewpoint of model.png: above and behind the volume centre, looking at it.
Eigen::Isometry3d overviewPose(const PipelineConfig& config);

}  // namespace sb
