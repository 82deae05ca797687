#pragma once
// Runs many `slambooster run` invocations (benchmarks, design-space exploration, profiling) as child
// processes of this executable, `parallel` at a time, each writing into its own directory. Resumable: a job
// whose summary.json says "complete" is skipped, so an interrupted command picks up where it stopped.
// Several processes (even on other machines sharing the directory) may work on one job list: a job is
// claimed with an exclusive `.claim` file kept alive by a heartbeat, and a claim whose process is gone or
// whose heartbeat stopped is taken over (claim.h).
// runJobs returns when every job is done, whoever ran it: it waits for the jobs other processes hold.

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pipeline/knobs.h"

#include "report/run_summary.h"

namespace sb::cli {

struct Job {
  std::string id;                    // shown in the progress, e.g. "kitchen / slambooster"
  std::string outDir;                // the run's --out
  std::vector<std::string> runArgs;  // arguments after `slambooster run` (sequence first), without --out
  // More arguments, asked for when the job starts (dse: a time limit from the runs finished so far).
  std::function<std::vector<std::string>()> argsAtStart;
};

// The absolute path of this executable (/proc/self/exe).
std::string selfExecutable();
// True when `outDir/summary.json` exists and says "complete": true.
bool jobDone(const std::string& outDir);
// summary.json of a finished job (throws sb::Error naming the file when it is missing or broken).
RunSummary readSummary(const std::string& outDir);

// Runs the jobs not done yet, `parallel` at a time, with a progress line on stderr (unless quiet). Each
// job's output goes to outDir/run.log. Throws sb::Error after all jobs ended when any failed, naming them
// and their logs.
void runJobs(const std::vector<Job>& jobs, int parallel, bool quiet);

// Every combination of the given knob values (pd1, pd2 of DEFAULT).
std::vector<Knobs> knobGrid(const std::vector<int>& csr, const std::vector<double>& icp, const std::vector<int>& pd0,
                            const std::vector<int>& ir);
// A directory-name-safe id of a knob setting, e.g. "csr2_icp1e-05_pd8-5-4_tr1_ir1".
std::string knobsId(const Knobs& knobs);
// The last path component of a sequence path without extension, e.g. "7scenes-redkitchen-a".
std::string sequenceName(const std::string& path);

}  // namespace sb::cli
