// `slambooster dse SEQ`: exhaustive design-space exploration of fixed knob settings on one sequence (the
// `offline` baseline). Every combination of the given csr, icp, pd0 and ir values runs as its own
// `slambooster run` (resumable, --jobs in parallel, several dse processes may share --out); results.csv
// lists them all (ATE nan where it is undefined: such a setting is out of bound) and best.json holds the
// fastest setting whose ATE is under the bound with enough frames tracked, ready for the `offline`
// controller ({"offline": {"result": ".../best.json"}}).
//
// Branch and bound: the settings run cheapest-looking first, and each run starts with --stop-after-ms set
// to the summed computation time of the fastest finished run within the bound so far. A run that passes it
// cannot be the fastest (every further frame only adds time), so it stops there; the answer is the one the
// full search would give from the same measurements. --no-prune runs every setting to the end.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>
#include <numeric>
#include <sstream>
#include <tuple>

#include "core/error.h"
#include "tools/slambooster/commands.h"
#include "tools/slambooster/machines.h"
#include "tools/slambooster/matrix_plan.h"
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
  bool noPrune = false;
  bool quiet = false;
  MatrixMode matrix;  // --plan, --run-index, --shard, --report-only
};

// Within the bound: ATE defined and under it, enough frames tracked, and run to the end.
bool withinBound(const RunSummary& s, const DseOptions& o) {
  if (s.stopped || !s.ate) return false;
  return s.ate->rmseM < o.maxAteM && s.trackedPercent >= o.minTrackedPercent;
}

// The computation time summed over the frames of the fastest finished run within the bound (infinity: none).
double fastestWithinBoundMs(const std::vector<Job>& jobs, const DseOptions& o) {
  double best = std::numeric_limits<double>::infinity();
  for (const Job& j : jobs) {
    if (!jobDone(j.outDir)) continue;
    const RunSummary s = readSummary(j.outDir);
    if (withinBound(s, o)) best = std::min(best, s.computationMsPerFrame * double(s.frames));
  }
  return best;
}

// Coarser compute size, rarer integration, earlier ICP stop and fewer iterations first: the likely fast
// settings, so that a bound is known early.
std::vector<size_t> cheapestFirst(const std::vector<Knobs>& grid) {
  std::vector<size_t> order(grid.size());
  std::iota(order.begin(), order.end(), size_t{0});
  const auto key = [&grid](size_t i) {
    const Knobs& k = grid[i];
    return std::make_tuple(-k.csr, -k.integrationRate, -k.icpThreshold, k.pyramidIterations[0]);
  };
  std::stable_sort(order.begin(), order.end(), [&key](size_t a, size_t b) { return key(a) < key(b); });
  return order;
}

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
    if (!o.noPrune) {
      j.argsAtStart = [&jobs, &o]() -> std::vector<std::string> {
        const double limit = fastestWithinBoundMs(jobs, o);
        if (!std::isfinite(limit)) return {};
        std::ostringstream text;
        text << std::setprecision(17) << limit;
        return {"--stop-after-ms", text.str()};
      };
    } else if (jobDone(j.outDir) && readSummary(j.outDir).stopped) {
      std::filesystem::remove(j.outDir + "/summary.json");  // stopped by an earlier, pruning dse: run it again
    }
    jobs.push_back(j);
  }
  std::vector<Job> ordered;
  for (size_t i : cheapestFirst(grid)) ordered.push_back(jobs[i]);
  if (runMatrixPart(o.matrix, ordered, o.jobs, o.quiet)) return;
  if (!o.matrix.reportOnly) runJobs(ordered, o.jobs, o.quiet);
  const std::vector<std::string> missing = missingRuns(ordered, "slambooster dse");

  std::vector<RunSummary> summaries;
  std::ofstream csv(o.out + "/results.csv");
  csv << "knobs,frames,tracked_percent,computation_ms_per_frame,ate_rmse_m,within_bound,stopped_at_frame\n";
  nlohmann::json best = nullptr;
  size_t stopped = 0;
  for (size_t i = 0; i < grid.size(); ++i) {
    if (!jobDone(jobs[i].outDir)) continue;  // missing: listed above, and in best.json
    const RunSummary s = readSummary(jobs[i].outDir);
    summaries.push_back(s);
    const bool wasStopped = s.stopped.has_value();
    stopped += wasStopped;
    // With ground truth, a run whose ATE is undefined (e.g. tracking never moved the camera) is out of bound.
    if (!wasStopped && !s.ate && s.ateError.empty())
      throw Error("dse needs ground truth: '" + o.sequence + "' gave no ATE (" + jobs[i].outDir + ")");
    // A stopped run's ATE covers only its first frames: not a result.
    const double ate = s.ate && !wasStopped ? s.ate->rmseM : NAN;
    const double ms = s.computationMsPerFrame, tracked = s.trackedPercent;
    const bool ok = withinBound(s, o);
    csv << '"' << formatKnobs(grid[i]) << "\"," << s.frames << "," << tracked << "," << ms << "," << ate << ","
        << ok << "," << (wasStopped ? std::to_string(s.stopped->atFrame) : "") << "\n";
    if (ok && (best.is_null() || ms < best["computation_ms_per_frame"].get<double>()))
      best = {{"knobs", formatKnobs(grid[i])}, {"computation_ms_per_frame", ms}, {"ate_rmse_m", ate},
              {"tracked_percent", tracked}, {"run", jobs[i].outDir}};
  }
  const nlohmann::json result = {{"sequence", o.sequence}, {"max_ate_m", o.maxAteM},
                                 {"min_tracked_percent", o.minTrackedPercent}, {"frames", o.frames},
                                 {"settings", grid.size()}, {"stopped_early", stopped}, {"best", best}};
  nlohmann::json withContext = result;
  // Where the settings were timed; ranking across kinds of machine is said, not hidden.
  const MachineMix machines = machineMix(summaries);
  withContext["machines"] = machines.kinds;
  withContext["hosts"] = machines.hosts;
  if (machines.mixed()) {
    withContext["mixed_machines"] = machines.note("the settings' ranking and the best setting");
    std::cout << withContext["mixed_machines"].get<std::string>() << "\n";
  }
  if (!missing.empty()) {
    withContext["missing_runs"] = missing;
    std::cout << "incomplete: " << missing.size() << " of " << grid.size()
              << " settings have not finished; the best is the best of those that did\n";
  }
  std::ofstream(o.out + "/best.json") << withContext.dump(2) << "\n";
  if (stopped)
    std::cout << stopped << " of " << grid.size()
              << " settings stopped early, slower than a setting within the bound (--no-prune runs them to the end)\n";
  if (best.is_null())
    std::cout << "no setting keeps ATE < " << o.maxAteM * 100 << " cm with >= " << o.minTrackedPercent << "% tracked\n";
  else
    std::cout << "best: " << best["knobs"].get<std::string>() << " at " << std::fixed << std::setprecision(1)
              << best["computation_ms_per_frame"].get<double>() << " ms/frame, ATE " << std::setprecision(2)
              << best["ate_rmse_m"].get<double>() * 100 << " cm\n";
  std::cout << "results in " << o.out << "/results.csv and " << o.out << "/best.json\n";
}

}  // namespace

void addDseCommand(CLI::App& app, const std::vector<std::string>& commandLine) {
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
  sub->add_flag("--no-prune", o->noPrune,
                "run every setting to the end (default: stop a run once it is slower than the fastest setting\n"
                "within the bound so far)");
  sub->add_flag("--quiet", o->quiet, "no progress");
  addMatrixOptions(*sub, o->matrix, commandLine);
  sub->callback([o] { dseCommand(*o); });
}

}  // namespace sb::cli
