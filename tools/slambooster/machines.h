#pragma once
// Which machines the runs of a matrix were timed on (summary.json "machine", runtime/summary_sink.h), and
// the sentence a report puts above its tables: times taken on different kinds of machine are not comparable,
// so a report, a dse or a profile that mixes them says so.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "report/run_summary.h"

namespace sb::cli {

struct MachineMix {
  std::vector<std::string> kinds;  // distinct "CPU model, N threads, backend device" (unknown: no record)
  std::vector<std::string> hosts;  // distinct host names
  bool mixed() const { return kinds.size() > 1; }
  // One sentence: where the runs ran ("Machine: ..."), or, when they mixed kinds of machine, that
  // `comparing` (what the report ranks) compares times from different machines. "" when there are no runs.
  std::string note(const std::string& comparing) const;
};

// From the summaries of the finished runs.
MachineMix machineMix(const std::vector<RunSummary>& summaries);

}  // namespace sb::cli
