#include "tools/slambooster/matrix_plan.h"

#include <unistd.h>

#include <charconv>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <stdexcept>

#include "core/error.h"
#include "core/exclusive_file.h"

namespace sb::cli {

namespace fs = std::filesystem;

namespace {

std::string shellQuote(const std::string& word) {
  std::string quoted = "'";
  for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// This invocation from its working directory, without the matrix options.
std::string baseLine(const MatrixMode& mode) {
  std::string line = "cd " + shellQuote(fs::current_path().string()) + " && " + shellQuote(selfExecutable());
  const std::vector<std::string>& args = mode.commandLine;
  for (size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--plan" || a == "--run-index" || a == "--run-dir" || a == "--shard") {
      ++i;  // and its value
      continue;
    }
    if (a == "--report-only" || a.rfind("--plan=", 0) == 0 || a.rfind("--run-index=", 0) == 0 || a.rfind("--run-dir=", 0) == 0 ||
        a.rfind("--shard=", 0) == 0)
      continue;
    line += " " + shellQuote(a);
  }
  return line;
}

// The command line of one run: --run-index, and --run-dir to check that the index still means that run.
std::string runLine(const MatrixMode& mode, size_t index, const Job& job) {
  return baseLine(mode) + " --run-index " + std::to_string(index) + " --run-dir " + shellQuote(job.outDir);
}

void parseShard(const std::string& text, size_t& index, size_t& count) {
  const size_t slash = text.find('/');
  try {
    if (slash == std::string::npos) throw std::invalid_argument("no /");
    if (text.find_first_not_of("0123456789/") != std::string::npos || slash == 0 || slash + 1 == text.size())
      throw std::invalid_argument("not two unsigned integers");
    size_t used = 0;
    index = std::stoul(text.substr(0, slash), &used);
    if (used != slash) throw std::invalid_argument("index");
    count = std::stoul(text.substr(slash + 1), &used);
    if (used != text.size() - slash - 1) throw std::invalid_argument("count");
  } catch (const std::exception&) {
    throw Error("--shard '" + text + "': expected I/N with 0 <= I < N, e.g. 0/4");
  }
  if (count == 0 || index >= count) throw Error("--shard '" + text + "': expected I/N with 0 <= I < N, e.g. 0/4");
}

}  // namespace

void addMatrixOptions(CLI::App& sub, MatrixMode& mode, const std::vector<std::string>& commandLine) {
  mode.commandLine = commandLine;
  auto* plan = sub.add_option("--plan", mode.planPath,
                              "Write the matrix as one shell command per run (line I+1 runs run I) to FILE and run\n"
                              "nothing: for Slurm arrays and GNU parallel (scripts/slurm_matrix.sh, parallel_matrix.sh)");
  // Checked as text before conversion: CLI11 would clamp a number past the range of `long`.
  const CLI::Validator runIndexRange(
      [](std::string& text) -> std::string {
        unsigned long long value = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (error != std::errc() || end != text.data() + text.size() ||
            value > static_cast<unsigned long long>(std::numeric_limits<long>::max()))
          return "--run-index '" + text + "': expected a run index from 0 to " +
                 std::to_string(std::numeric_limits<long>::max()) + " (see --plan)";
        return "";
      },
      "INDEX");
  const CLI::Validator shardFormat(
      [](std::string& text) -> std::string {
        size_t index = 0, count = 0;
        try {
          parseShard(text, index, count);
        } catch (const Error& e) {
          return e.what();
        }
        return "";
      },
      "I/N");
  auto* index = sub.add_option("--run-index", mode.runIndex, "Run only run I of the matrix (0-based; see --plan)")
                    ->check(runIndexRange);
  auto* runDir = sub.add_option("--run-dir", mode.runDir,
                                "With --run-index: the run's directory as the plan has it; refused when the index\n"
                                "now means another run (the matrix changed since the plan)");
  auto* shard = sub.add_option("--shard", mode.shard, "I/N: run the runs whose index is I modulo N")
                    ->check(shardFormat);
  auto* report = sub.add_flag("--report-only", mode.reportOnly,
                              "Run nothing: build the tables from the runs that finished and list the missing ones");
  plan->excludes(index)->excludes(shard)->excludes(report);
  index->excludes(shard)->excludes(report);
  runDir->needs(index);
  shard->excludes(report);
}

bool runMatrixPart(const MatrixMode& mode, const std::vector<Job>& jobs, int parallel, bool quiet) {
  if (!mode.planPath.empty()) {
    std::string text;
    for (size_t i = 0; i < jobs.size(); ++i) text += runLine(mode, i, jobs[i]) + "\n";
    if (fs::path(mode.planPath).has_parent_path()) fs::create_directories(fs::path(mode.planPath).parent_path());
    writeFileAtomically(mode.planPath, text);
    std::cout << jobs.size() << " runs in " << mode.planPath << " (run I is line I+1; Slurm: --array=0-"
              << (jobs.empty() ? 0 : jobs.size() - 1) << ")\nthen the report: " << baseLine(mode) << " --report-only\n";
    return true;
  }
  if (mode.runIndex >= 0) {
    if (static_cast<size_t>(mode.runIndex) >= jobs.size())
      throw Error("--run-index " + std::to_string(mode.runIndex) + ": the matrix has " + std::to_string(jobs.size()) +
                  " runs (0-" + std::to_string(jobs.size() - 1) + "); was the plan made with other options?");
    const Job& job = jobs[static_cast<size_t>(mode.runIndex)];
    if (!mode.runDir.empty() && mode.runDir != job.outDir)
      throw Error("--run-index " + std::to_string(mode.runIndex) + " is now the run in '" + job.outDir +
                  "', but the plan meant '" + mode.runDir + "': the matrix changed since the plan was written " +
                  "(other options, or dse/profile results that appeared since); write the plan again");
    runJobs({job}, 1, quiet);
    return true;
  }
  if (!mode.shard.empty()) {
    size_t index = 0, count = 1;
    parseShard(mode.shard, index, count);
    std::vector<Job> part;
    for (size_t i = index; i < jobs.size(); i += count) part.push_back(jobs[i]);
    runJobs(part, parallel, quiet);
    return true;
  }
  return false;
}

std::vector<std::string> missingRuns(const std::vector<Job>& jobs, const std::string& command) {
  std::vector<std::string> missing;
  for (const Job& j : jobs)
    if (!jobDone(j.outDir)) missing.push_back(j.id + " (" + j.outDir + ")");
  if (!missing.empty()) {
    std::cerr << command << ": " << missing.size() << " of " << jobs.size()
              << " runs missing (not run, still running, or failed: see run.log in their directories):\n";
    for (const std::string& m : missing) std::cerr << "  " << m << "\n";
  }
  return missing;
}

void writeFileAtomically(const std::string& path, const std::string& text) {
  // A new temporary of a name no one made before (core/exclusive_file.h), renamed over `path`.
  TemporaryFile tmp(path);
  if (std::fwrite(text.data(), 1, text.size(), tmp.stream()) != text.size())
    throw Error("cannot write '" + tmp.path() + "': " + std::strerror(errno) + " (check the output directory)");
  tmp.commit();
}

}  // namespace sb::cli
