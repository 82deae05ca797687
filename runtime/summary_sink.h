#pragma once
// summary.json of a run (report/run_summary.h RunSummary, written whole): what ran (set by the run setup),
// frame counts, % tracked, mean computation time and stage times per frame, controller cost, corrections and
// trigger counts, time per knob setting, and the ATE against the sequence's ground truth when it has one (the
// trajectory read back from its file at each flush: memory does not grow with the run). Rewritten atomically
// (temporary file + rename) after every frame (without the ATE) and on every flush (with it), so a reader
// never sees half a file and a killed run keeps a summary of every frame but at most the one in hand. With
// the segment store of rotated outputs, a rewrite that fails because the disk is full removes the oldest
// segment and writes again (the service goes on).
//
// The last summary of a run (the one that says "complete", true or false) is written even on a full disk
// (issue 53 finding 8): room for it is kept aside from the start (core/reserved_file.h,
// "summary.json.reserve.<random>": kSummaryReserveBytes, grown to twice the largest summary written so far),
// and when its rewrite fails the summary goes into that room instead. The per-frame snapshots never use it.

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/reserved_file.h"
#include "core/segment_store.h"
#include "core/tracking_state.h"
#include "core/trajectory.h"
#include "eval/trajectory_eval.h"
#include "report/run_summary.h"
#include "runtime/output_sink.h"

namespace sb {

// Running totals of a run: the counts of its RunSummary.
struct RunStats {
  size_t frames = 0, trackingAttempted = 0, tracked = 0, integrated = 0, corrected = 0, halfWishes = 0;
  size_t unconstrained = 0;  // frames whose ICP geometry left a motion free (tracking quality)
  size_t retracked = 0;      // frames tracked a second time at other knobs
  size_t halfApplied = 0;    // frames run with half-precision storage
  StageTimes stageSums;         // ms summed over frames
  double controllerMsSum = 0.0;
  std::map<std::string, size_t> triggerCounts;
  std::map<std::string, size_t> knobCounts;  // formatKnobs(knobs) -> frames run with them
  std::map<std::string, size_t> controllerCounts;  // controller name -> frames it decided (a daemon may switch)
  // Tracking state (core/tracking_state.h): frames per state; stretches of lost frames (a stretch ends at
  // a frame that is not lost); recoveries (stretches ended by a relocalisation) and their length in frames.
  std::array<size_t, kTrackingStateCount> stateFrames{};
  size_t lostStretches = 0, longestLost = 0, currentLost = 0;
  size_t recoveries = 0, recoveryFramesSum = 0, longestRecovery = 0;

  void add(const FrameRecord& record);
  double computationMsPerFrame() const { return frames ? stageSums.computationMs() / frames : 0.0; }
  double trackedPercent() const { return trackingAttempted ? 100.0 * tracked / trackingAttempted : 0.0; }
  // Sets the counts of `summary` (frames ... tracking_state) from these totals.
  void fill(RunSummary& summary) const;
};

// Where a run was timed, for summary.json's "machine": host name, CPU model (/proc/cpuinfo), cores online,
// the worker threads the run used, and the compute backend and its device. Runs timed on different machines
// are not comparable; bench, dse and profile say so when they mix them.
MachineInfo thisMachine(unsigned threadsUsed, const std::string& backend, const std::string& device);
// The CPU model of this machine ("model name" in /proc/cpuinfo, or the "Hardware"/"Processor" line on ARM;
// "unknown" when none).
std::string cpuModel();

// The room kept aside for the last summary at the least (SummarySink; it grows to twice the largest summary
// written: summaries are 2-10 KB).
constexpr uint64_t kSummaryReserveBytes = uint64_t(16) << 10;

class SummarySink final : public OutputSink {
 public:
  // `groundTruthPath`: TUM trajectory to compute the ATE against ("" = none). `header`: what ran (sequence,
  // controller, config, machine ...); header() may set more later (energy, completion). The counts and the
  // ATE are the sink's. `segments`: the retention that makes room on a full disk (nullptr: a full disk fails
  // the write). Keeps kSummaryReserveBytes aside beside `path` (throws sb::DiskFullError naming summary.json
  // when the disk cannot hold them: said at the start rather than at the end).
  SummarySink(const std::string& path, const std::string& groundTruthPath, RunSummary header,
              std::shared_ptr<SegmentStore> segments = nullptr);
  void onFrame(const FrameRecord& record) override;
  void flush() override;

  // The fields written with every frame's counts, typed (report/run_summary.h): set them here (the mesh counts:
  // runtime/map_slabs.cpp), the next write carries them.
  RunSummary& header() { return header_; }
  // Where the ATE's trajectory comes from: read back at each flush (the trajectory file), never kept in
  // memory.
  void setTrajectorySource(std::function<Trajectory()> read) { readTrajectory_ = std::move(read); }
  const RunStats& stats() const { return stats_; }
  // The ATE of the frames so far (computed at the last flush), when there is ground truth.
  const std::optional<AteResult>& ate() const { return ate_; }
  // The summary written at the last flush.
  const RunSummary& summary() const { return summary_; }

 private:
  // Writes `summary` (temporary file + rename); the last one (`complete` set) into the room kept aside when
  // the disk refuses it. Throws sb::WriteError naming summary.json.
  void write(const RunSummary& summary);

  std::string path_;
  std::string groundTruthPath_;
  std::shared_ptr<SegmentStore> segments_;
  std::unique_ptr<ReservedFile> reserve_;  // for the last summary; null once used
  std::optional<Trajectory> groundTruth_;
  RunSummary header_;
  RunStats stats_;
  std::function<Trajectory()> readTrajectory_;
  std::optional<AteResult> ate_;
  RunSummary summary_;
};

}  // namespace sb
