// `slambooster dse SEQ`: exhaustive design-space exploration of fixed knob settings on one sequence (the
// `offline` baseline). Every combination of the given csr, icp, pd0 and ir values runs as its own
// `slambooster run` (resumable, --jobs in parallel, several dse processes may share --out); results.csv
// lists them all (ATE nan where it is undefined: such a setting is out of bound) and best.json holds the fastest setting whose ATE is under the bound with enough frames
// tracked, ready for the `offline` controller ({"offline": {"result": ".../best.json"}}).

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>

#include "core/error.h"
#include "tools/slambooster/commands.h"
#include "tools/slambooster/run_jobs.h"

namespace sb::cli {

namespace {

struct DseOptions {
  std::string sequence, out, config;
  std::vector<int> csr{1, 2, 4, 8};
  std::vector<double> icp{0.0, 1e-6, 1e-5, 1e-4, 1e-3, 1.0};
  std::vector<int> pd0{10, 8, 6, 4};
  std::vector<int> ir{1};
  double maxAteM = 0.05;
  double minTrackedPercent = 99.0;
  size_t frames = 0;
  int jobs = 1;
  unsigned threads = 1;
  bool quiet = false;
};

void dseCommand(const DseOptions& o) {
  const std::vector<Knobs> grid = knobGrid(o.csr, o.icp, o.pd0, o.ir);
  std::vector<Job> jobs;
  for (const Knobs& k : grid) {
    Job j;
    j.id = knobsId(k);
    j.outDir = o.out + "/runs/" + j.id;
    j.runArgs = {o.sequence, "--controller", "fixed", "--knobs", formatKnobs(k), "--threads", std::to_string(o.threads),
                 "--frames", std::to_string(o.frames)};
    if (!o.config.empty()) j.runArgs.insert(j.runArgs.end(), {"--config", o.config});
    jobs.push_back(j);
  }
  runJobs(jobs, o.jobs, o.quiet);

  std::ofstream csv(o.out + "/results.csv");
  csv << "knobs,frames,tracked_percent,computation_ms_per_frame,ate_rmse_m,within_bound\n";
  nlohmann::json best = nullptr;
  for (size_t i = 0; i < grid.size(); ++i) {
    const nlohmann::json s = readSummary(jobs[i].outDir);
    // With ground truth, a run whose ATE is undefined (e.g. tracking never moved the camera) is out of bound.
    if (!s.contains("ate") && !s.contains("ate_error"))
      throw Error("dse needs ground truth: '" + o.sequence + "' gave no ATE (" + jobs[i].outDir + ")");
    const double ate = s.contains("ate") ? s["ate"]["rmse_m"].get<double>() : NAN;
    const double ms = s["computation_ms_per_frame"], tracked = s["tracked_percent"];
    const bool ok = ate < o.maxAteM && tracked >= o.minTrackedPercent;  // false for NaN
    csv << formatKnobs(grid[i]) << "," << s["frames"] << "," << tracked << "," << ms << "," << ate << "," << ok << "\n";
    if (ok && (best.is_null() || ms < best["computation_ms_per_frame"].get<double>()))
      best = {{"knobs", formatKnobs(grid[i])}, {"computation_ms_per_frame", ms}, {"ate_rmse_m", ate},
              {"tracked_percent", tracked}, {"run", jobs[i].outDir}};
  }
  const nlohmann::json result = {{"sequence", o.sequence}, {"max_ate_m", o.maxAteM},
                                 {"min_tracked_percent", o.minTrackedPercent}, {"frames", o.frames},
                                 {"settings", grid.size()}, {"best", best}};
  std::ofstream(o.out + "/best.json") << result.dump(2) << "\n";
  if (best.is_null())
    std::cout << "no setting keeps ATE < " << o.maxAteM * 100 << " cm with >= " << o.minTrackedPercent << "% tracked\n";
  else
    std::cout << "best: " << best["knobs"].get<std::string>() << " at " << std::fixed << std::setprecision(1)
              << best["computation_ms_per_frame"].get<double>() << " ms/frame, ATE " << std::setprecision(2)
              << best["ate_rmse_m"].get<double>() * 100 << " cm\n";
  std::cout << "results in " << o.out << "/results.csv and " << o.out << "/best.json\n";
}

}  // namespace

void addDseCommand(CLI::App& app) {
  auto o = std::make_shared<DseOptions>();
  auto* sub = app.add_subcommand("dse", "Exhaustive search of fixed knob settings on one sequence (offline best)");
  sub->add_option("sequence", o->sequence, "Sequence with ground truth")->required();
  sub->add_option("--out", o->out, "Output directory (resumable: finished runs are kept)")->required();
  sub->add_option("--config", o->config, "Pipeline config (JSON) for every run");
  sub->add_option("--csr", o->csr, "csr values")->delimiter(',');
  sub->add_option("--icp", o->icp, "icp threshold values")->delimiter(',');
  sub->add_option("--pd0", o->pd0, "finest-level ICP iteration values")->delimiter(',');
  sub->add_option("--ir", o->ir, "integration rate values")->delimiter(',');
  sub->add_option("--max-ate", o->maxAteM, "ATE bound, metres");
  sub->add_option("--min-tracked", o->minTrackedPercent, "minimum % of frames tracked");
  sub->add_option("--frames", o->frames, "frames per run (0 = all)");
  sub->add_option("--jobs", o->jobs, "runs in parallel")->check(CLI::Range(1, 256));
  sub->add_option("--threads", o->threads, "worker threads per run");
  sub->add_flag("--quiet", o->quiet, "no progress");
  sub->callback([o] { dseCommand(*o); });
}

}  // namespace sb::cli
