#pragma once
// The standard outputs of a run in one directory: trajectory.tum, frames.jsonl and summary.json; with a
// segment store the first two are rotated (core/rotating_file.h) and summary.json stays one file, whose
// rewrite on a full disk removes the oldest segments as theirs do.

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "core/segment_store.h"
#include "runtime/frame_log_sink.h"
#include "runtime/slam_runner.h"
#include "runtime/summary_sink.h"
#include "runtime/trajectory_sink.h"

namespace sb {

struct StandardOutputs {
  TrajectorySink* trajectory = nullptr;  // owned by the runner
  FrameLogSink* frameLog = nullptr;
  SummarySink* summary = nullptr;
};

// Creates `dir` when missing and adds the three sinks to `runner`. `groundTruthPath` ("" = none) gives the
// summary its ATE; `header` starts summary.json (what ran); `comment` heads the trajectory file; `segments`
// (nullptr: single files) rotates the trajectory and the frame log. Throws sb::Error naming the directory or
// file that cannot be written.
StandardOutputs addStandardOutputs(SlamRunner& runner, const std::string& dir,
                                   const std::string& groundTruthPath, const RunSummary& header,
                                   const std::string& comment,
                                   std::shared_ptr<SegmentStore> segments = nullptr);

}  // namespace sb
