#pragma once
// The configuration table of the application-agnostic `tc` controller: knob settings with their profiled
// speedup over DEFAULT and ATE on the profiling sequences, Pareto-optimal (no entry is both slower and less
// accurate than another). Built by `slambooster profile`, stored as JSON:
//   {"reference_ms_per_frame": 150.2, "sequences": ["..."],
//    "entries": [{"knobs": "csr=1,icp=1e-05,pd=10:5:4,tr=1,ir=1", "ms_per_frame": 150.2, "speedup": 1.0,
//                 "ate_m": 0.021}, ...]}

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "pipeline/knobs.h"

namespace sb {

struct TcEntry {
  Knobs knobs;
  double msPerFrame = 0.0;  // mean computation ms/frame over the profiling sequences
  double speedup = 1.0;     // reference_ms_per_frame / msPerFrame
  double ateM = 0.0;        // worst ATE RMSE over the profiling sequences, metres
};

struct TcTable {
  double referenceMsPerFrame = 0.0;
  std::vector<std::string> sequences;
  std::vector<TcEntry> entries;  // by increasing speedup
};

// Keeps the Pareto-optimal entries (higher speedup and lower ATE are better), sorted by increasing speedup.
std::vector<TcEntry> paretoFront(std::vector<TcEntry> candidates);

nlohmann::json tcTableToJson(const TcTable& table);
// Throws sb::Error naming `where` and the entry on malformed tables or an empty one.
TcTable tcTableFromJson(const nlohmann::json& j, const std::string& where);
TcTable loadTcTable(const std::string& path);

}  // namespace sb
