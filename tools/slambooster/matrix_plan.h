#pragma once
// How bench, dse and profile run their matrix of jobs: all in this process (the default), or spread over
// machines by an engine that already exists (Slurm job arrays, GNU parallel): --plan FILE writes the matrix
// as one self-contained shell command per line (line I+1 is run I: `cd DIR && slambooster ... --run-index
// I`), --run-index I runs exactly run I and --shard I/N every run whose index is I modulo N, into the shared
// --out, kept consistent by the jobs' claim files (claim.h). --report-only runs nothing: it builds the tables
// from the runs that finished and says which are missing.

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "tools/slambooster/run_jobs.h"

namespace sb::cli {

struct MatrixMode {
  std::string planPath;  // --plan: write the plan here, run nothing
  long runIndex = -1;    // --run-index: run only this one (-1: not given)
  std::string runDir;    // --run-dir: the run directory the plan meant by --run-index (a check)
  std::string shard;     // --shard I/N ("": not given)
  bool reportOnly = false;
  std::vector<std::string> commandLine;  // this invocation's arguments (argv), for the plan's lines
};

// Adds --plan, --run-index, --shard and --report-only (mutually exclusive) to a matrix subcommand. The
// command line is that of this process (main's argv).
void addMatrixOptions(CLI::App& sub, MatrixMode& mode, const std::vector<std::string>& commandLine);

// Does what --plan, --run-index or --shard ask, with `jobs` indexed in order; returns false when none was
// given (the command runs every job itself, or only reports). Throws sb::Error for an index out of range
// or a malformed shard, and, like runJobs, when a run failed.
bool runMatrixPart(const MatrixMode& mode, const std::vector<Job>& jobs, int parallel, bool quiet);

// The jobs not finished (no complete summary.json), as "id (outDir)"; printed on stderr as "<command>: N of
// M runs missing: ..." when there are any.
std::vector<std::string> missingRuns(const std::vector<Job>& jobs, const std::string& command);

// Writes `text` to `path` through a temporary file and a rename, so that processes writing the same file at
// once (array tasks writing the same config) never leave or read a half-written one.
void writeFileAtomically(const std::string& path, const std::string& text);

}  // namespace sb::cli
