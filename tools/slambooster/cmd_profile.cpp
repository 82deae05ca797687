// `slambooster profile SEQ...`: builds the configuration table of the application-agnostic `tc` controller.
// Runs DEFAULT and every knob setting of a grid on each profiling sequence (resumable, --jobs in parallel),
// then keeps the Pareto-optimal settings by speedup over DEFAULT (mean ms/frame over the sequences) and
// worst ATE, and writes them as the table `tc` reads ({"tc": {"table": ".../tc_table.json"}}).

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>

#include "controller/tc_table.h"
#include "core/error.h"
#include "tools/slambooster/commands.h"
#include "tools/slambooster/machines.h"
#include "tools/slambooster/matrix_plan.h"
#include "tools/slambooster/run_jobs.h"

namespace sb::cli {

namespace {

struct ProfileOptions {
  std::vector<std::string> sequences;
  std::string out, config;
  std::vector<int> csr{1, 2, 4, 8};
  std::vector<double> icp{1e-5, 1e-4, 1e-3};
  std::vector<int> pd0{10, 6, 4};
  std::vector<int> ir{1, 2};
  size_t frames = 0;
  int jobs = 1;
  unsigned threads = 1;
  bool quiet = false;
  MatrixMode matrix;  // --plan, --run-index, --shard, --report-only
};

void profileCommand(const ProfileOptions& o) {
  std::vector<Knobs> grid = knobGrid(o.csr, o.icp, o.pd0, o.ir);
  const Knobs reference = knobPreset("default");
  if (std::find(grid.begin(), grid.end(), reference) == grid.end()) grid.insert(grid.begin(), reference);
  std::vector<Job> jobs;
  for (const std::string& seq : o.sequences)
    for (const Knobs& k : grid) {
      Job j;
      j.id = sequenceName(seq) + " / " + knobsId(k);
      j.outDir = o.out + "/runs/" + sequenceName(seq) + "/" + knobsId(k);
      j.runArgs = {seq, "--controller", "fixed", "--knobs", formatKnobs(k), "--threads", std::to_string(o.threads),
                   "--frames", std::to_string(o.frames)};
      if (!o.config.empty()) j.runArgs.insert(j.runArgs.end(), {"--config", o.config});
      jobs.push_back(j);
    }
  if (runMatrixPart(o.matrix, jobs, o.jobs, o.quiet)) return;
  if (!o.matrix.reportOnly) runJobs(jobs, o.jobs, o.quiet);
  if (!missingRuns(jobs, "slambooster profile").empty())
    throw Error("profile: the table needs every setting on every profiling sequence; run the missing runs (the "
                "same command without --report-only, or the plan's lines for them), then report again");
  std::vector<RunSummary> summaries;

  std::vector<TcEntry> candidates;
  double referenceMs = 0;
  for (size_t g = 0; g < grid.size(); ++g) {
    TcEntry e;
    e.knobs = grid[g];
    bool ateDefined = true;
    for (size_t s = 0; s < o.sequences.size(); ++s) {
      const RunSummary summary = readSummary(jobs[s * grid.size() + g].outDir);
      summaries.push_back(summary);
      if (!summary.ate && summary.ateError.empty())
        throw Error("profile needs ground truth: '" + o.sequences[s] + "' gave no ATE");
      e.msPerFrame += summary.computationMsPerFrame / double(o.sequences.size());
      if (summary.ate)
        e.ateM = std::max(e.ateM, summary.ate->rmseM);
      else
        ateDefined = false;
    }
    if (grid[g] == reference) referenceMs = e.msPerFrame;
    // A setting whose ATE is undefined on a profiling sequence (tracking never moved the camera) has no
    // known error, so it cannot be in the table.
    if (ateDefined)
      candidates.push_back(e);
    else
      std::cerr << "profile: " << formatKnobs(grid[g]) << " left out: ATE undefined on a profiling sequence\n";
  }
  if (candidates.empty())
    throw Error("profile: no setting has a defined ATE on every profiling sequence (see the runs' summary.json "
                "ate_error in " + o.out + "/runs); profile on sequences where the camera moves");
  for (TcEntry& e : candidates) e.speedup = referenceMs / e.msPerFrame;
  TcTable table;
  table.referenceMsPerFrame = referenceMs;
  table.sequences = o.sequences;
  table.entries = paretoFront(candidates);
  const std::string path = o.out + "/tc_table.json";
  nlohmann::json tableJson = tcTableToJson(table);
  const MachineMix machines = machineMix(summaries);
  tableJson["machines"] = machines.kinds;  // where the speedups were timed (the tc controller ignores it)
  tableJson["hosts"] = machines.hosts;
  if (machines.mixed()) {
    tableJson["mixed_machines"] = machines.note("the speedups and the Pareto front");
    std::cout << tableJson["mixed_machines"].get<std::string>() << "\n";
  }
  std::ofstream(path) << tableJson.dump(2) << "\n";
  std::cout << std::fixed;
  for (const TcEntry& e : table.entries)
    std::cout << std::setprecision(2) << "speedup " << e.speedup << "  ATE " << e.ateM * 100 << " cm  "
              << formatKnobs(e.knobs) << "\n";
  std::cout << table.entries.size() << " Pareto-optimal of " << grid.size() << " settings; table in " << path << "\n";
}

}  // namespace

void addProfileCommand(CLI::App& app, const std::vector<std::string>& commandLine) {
  auto o = std::make_shared<ProfileOptions>();
  auto* sub = app.add_subcommand("profile", "Build the tc controller's configuration table from profiling sequences");
  sub->add_option("sequences", o->sequences, "Profiling sequences (with ground truth)")->required();
  sub->add_option("--out", o->out, "Output directory (resumable)")->required();
  sub->add_option("--config", o->config, "Pipeline config (JSON) for every run");
  sub->add_option("--csr", o->csr, "csr values")->delimiter(',');
  sub->add_option("--icp", o->icp, "icp threshold values")->delimiter(',');
  sub->add_option("--pd0", o->pd0, "finest-level ICP iteration values")->delimiter(',');
  sub->add_option("--ir", o->ir, "integration rate values")->delimiter(',');
  sub->add_option("--frames", o->frames, "frames per run (0 = all)");
  sub->add_option("--jobs", o->jobs, "runs in parallel")->check(CLI::Range(1, 256));
  sub->add_option("--threads", o->threads, "worker threads per run");
  sub->add_flag("--quiet", o->quiet, "no progress");
  addMatrixOptions(*sub, o->matrix, commandLine);
  sub->callback([o] { profileCommand(*o); });
}

}  // namespace sb::cli
