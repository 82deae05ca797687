#pragma once
// Everything a report shows about one run directory (the outputs of `slambooster run`): summary.json,
// frames.jsonl, trajectory.tum, model.png, mesh.ply, plus the ground truth found through the summary's
// sequence path (or given explicitly). Missing or damaged inputs become problems, never exceptions, except
// when the directory itself does not exist or holds none of the run's files.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/trajectory.h"
#include "eval/trajectory_eval.h"
#include "report/frame_log.h"
#include "report/run_summary.h"

namespace sb::report {

// The navigation map a run wrote (navmap/: map.pgm and map.yaml in map_server's conventions, map_frame.json).
struct NavGrid {
  Image<uint8_t> cells;           // map.pgm as stored: row 0 the top (the largest y); 0 occupied, 254 free, 205 unknown
  double resolutionM = 0.05;      // map.yaml resolution, metres per cell
  double originX = 0, originY = 0;  // map.yaml origin: the bottom-left corner of the bottom-left cell, metres
  Eigen::Isometry3d T_world_to_map = Eigen::Isometry3d::Identity();  // map_frame.json (volume frame -> map)
  std::string up;                 // map_frame.json "source": how up was found (mount, floor, odometry)
};

struct RunData {
  std::string dir;
  std::string label;                     // short name for legends (the directory name)
  std::optional<RunSummary> summary;     // summary.json when it parsed (report/run_summary.h)
  nlohmann::json summaryJson;            // the same file as written, every key (null when it did not parse)
  FrameLog frames;
  Trajectory trajectory;                 // trajectory.tum (volume frame); empty when absent
  std::string groundTruthPath;           // empty when none was found
  Trajectory groundTruth;
  std::optional<AteResult> ate;          // estimate vs ground truth (alignment, per-frame ITE)
  // The wheels' odometry the run was given (summary.json odometry.source when it is a TUM file, else the
  // sequence's odometry.txt): T_camera_to_odom. Empty when the run had none or the file is gone.
  Trajectory wheels;
  std::string wheelsPath;
  std::string wheelsWhy;                 // why `wheels` is empty (no odometry, file missing, ...)
  std::optional<NavGrid> grid;           // map.pgm + map.yaml + map_frame.json when all three read
  std::string gridWhy;                   // why `grid` is empty
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
