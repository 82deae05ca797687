#pragma once
// Everything a report shows about one run directory (the outputs of `slambooster run`): summary.json,
// frames.jsonl, trajectory.tum, model.png, mesh.ply, plus the ground truth found through the summary's
// sequence path (or given explicitly). Missing or damaged inputs become problems, never exceptions, except
// when the directory itself does not exist or holds none of the run's files.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/trajectory.h"
#include "eval/trajectory_eval.h"
#include "report/frame_log.h"
#include "report/run_summary.h"

namespace sb::report {

struct RunData {
  std::string dir;
  std::string label;                     // short name for legends (the directory name)
  std::optional<RunSummary> summary;     // summary.json when it parsed (report/run_summary.h)
  FrameLog frames;
  Trajectory trajectory;                 // trajectory.tum (volume frame); empty when absent
  std::string groundTruthPath;           // empty when none was found
  Trajectory groundTruth;
  std::optional<AteResult> ate;          // estimate vs ground truth (alignment, per-frame ITE)
  std::string modelPath, meshPath;       // empty when the file is absent
  std::vector<std::string> problems;     // what could not be read, each naming the file
  std::vector<std::string> notes;        // neutral facts (e.g. "no ground truth: ...")
};

struct RunLoadOptions {
  std::string groundTruth;  // TUM file; empty = `<summary.sequence>/groundtruth.txt` when it exists
};

// Throws sb::Error when `dir` is not a directory or holds none of summary.json, frames.jsonl,
// trajectory.tum, model.png.
RunData loadRun(const std::string& dir, const RunLoadOptions& options = {});

}  // namespace sb::report
