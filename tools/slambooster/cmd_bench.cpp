// `slambooster bench SEQ...`: the paper's experiments as one command. Runs every sequence under every
// controller (resumable, --jobs runs in parallel, progress on stderr), evaluates each trajectory against the
// sequence's ground truth (or, without one, the ACCURATE run's trajectory, as in the paper) and writes
// results.csv, report.md (main table DEFAULT vs SLAMBooster with the geometric mean, the incremental study,
// PID vs step, online vs offline, the TC table: reference velocities x profiling sets, one set per
// --tc-table), SVG plots (time and ATE bars, the per-frame trace) and report.html (all of these in one page,
// with links to each run's report.html).

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>

#include "controller/tc_table.h"
#include "core/config_reader.h"
#include "core/error.h"
#include "core/input_file.h"
#include "core/json_text.h"
#include "core/trajectory.h"
#include "drivers/sequence.h"
#include "eval/trajectory_eval.h"
#include "pipeline/knobs.h"
#include "report/run_report.h"
#include "tools/slambooster/bench_plots.h"
#include "tools/slambooster/bench_report.h"
#include "tools/slambooster/commands.h"
#include "tools/slambooster/machines.h"
#include "tools/slambooster/matrix_plan.h"
#include "tools/slambooster/run_jobs.h"

namespace sb::cli {

namespace {

namespace fs = std::filesystem;

struct BenchOptions {
  std::vector<std::string> sequences;
  std::string out, config, dseDir, plotSequence, powerConfig;
  std::vector<std::string> tcTables;  // --tc-table [NAME=]PATH, repeated
  std::vector<std::string> fixedColumns;  // --fixed LABEL=KNOBS, repeated
  std::vector<std::string> controllers{"default", "accurate", "pid", "pid+surface", "pid+surface+correction",
                                       "slambooster", "adaptive", "step"};
  std::vector<double> tcVelocities{0.005, 0.01, 0.02};
  size_t frames = 0;
  int jobs = 1;
  unsigned threads = 1;
  bool noOdometry = false;  // --no-odometry: passed to every run
  bool quiet = false;
  MatrixMode matrix;  // --plan, --run-index, --shard, --report-only
};

// The config file of one bench column: the user's config with the controller section's name (and extra
// section keys) set.
std::string writeColumnConfig(const BenchOptions& o, const std::string& label, const std::string& name,
                              const nlohmann::json& sectionPatch) {
  nlohmann::json j = o.config.empty() ? nlohmann::json::object() : readJsonConfig(o.config, "config file");
  nlohmann::json& c = j["controller"];
  if (c.is_string() || c.is_null()) c = nlohmann::json::object();
  c["name"] = name;
  for (auto& [section, values] : sectionPatch.items())
    for (auto& [key, value] : values.items()) c[section][key] = value;
  std::string file = label;
  for (char& ch : file)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '.') ch = '_';
  const std::string path = o.out + "/configs/" + file + ".json";
  fs::create_directories(o.out + "/configs");
  writeFileAtomically(path, j.dump(2) + "\n");  // array tasks write the same configs at once
  return path;
}

bool isSetName(const std::string& name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.' || c == '+';
  });
}

// The profiling sets of --tc-table [NAME=]PATH: NAME defaults to the table's directory name; one table
// given without NAME keeps the columns tc@v (as before there could be several), otherwise tc-NAME@v.
// Each table is loaded here, so a missing or malformed one stops the bench before any run.
std::vector<BenchTcSet> tcSets(const std::vector<std::string>& args) {
  std::vector<BenchTcSet> sets;
  for (const std::string& arg : args) {
    BenchTcSet t;
    const size_t eq = arg.find('=');
    const bool named = eq != std::string::npos && arg.substr(0, eq).find('/') == std::string::npos;
    t.path = named ? arg.substr(eq + 1) : arg;
    t.name =
        named ? arg.substr(0, eq) : fs::absolute(t.path).lexically_normal().parent_path().filename().string();
    if (!isSetName(t.name))
      throw Error("--tc-table '" + arg + "': the set name '" + t.name +
                  "' is not usable in column labels (letters, digits, - _ . +); name the set as NAME=PATH");
    for (const BenchTcSet& other : sets)
      if (other.name == t.name)
        throw Error("--tc-table '" + arg + "': the set name '" + t.name + "' is also that of '" + other.path +
                    "'; give each table its own name as NAME=PATH");
    for (const std::string& s : loadTcTable(t.path).sequences) t.profiledOn.push_back(sequenceName(s));
    t.path = fs::absolute(t.path).lexically_normal().string();
    t.prefix = args.size() == 1 && !named ? "tc" : "tc-" + t.name;
    sets.push_back(t);
  }
  return sets;
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw Error("cannot write '" + path + "'");
}

std::string missingList(const std::vector<std::string>& missing) {
  std::string text;
  for (size_t i = 0; i < missing.size() && i < 20; ++i) text += (i ? ", " : "") + missing[i];
  return missing.size() > 20 ? text + " and " + std::to_string(missing.size() - 20) + " more" : text;
}

// The runs of a bench: its columns (label -> config file), the jobs and where each (sequence, column) runs.
struct BenchPlan {
  std::vector<BenchTcSet> tables;
  std::vector<std::string> labels;  // the columns, offline aside
  std::vector<Job> jobs;
  std::map<std::pair<std::string, std::string>, std::string> dirOf;  // (sequence name, label) -> output dir
  std::map<std::string, std::string> groundTruth;                    // sequence name -> TUM file ("" = none)
};

BenchPlan planBench(const BenchOptions& o) {
  BenchPlan plan;
  // First, so that a bad table stops the bench before anything is written.
  plan.tables = tcSets(o.tcTables);
  const std::vector<BenchTcSet>& tables = plan.tables;
  // Columns: label -> (controller name, config file).
  std::vector<std::string>& labels = plan.labels;
  labels = o.controllers;
  if (std::find(labels.begin(), labels.end(), "accurate") == labels.end()) labels.push_back("accurate");
  std::map<std::string, std::string> configOf;
  for (const std::string& c : labels) configOf[c] = writeColumnConfig(o, c, c, nlohmann::json::object());
  // --fixed LABEL=KNOBS: a fixed setting as a column (e.g. the best single setting for a whole set).
  for (const std::string& arg : o.fixedColumns) {
    const size_t eq = arg.find('=');
    const std::string label = eq == std::string::npos ? "" : arg.substr(0, eq);
    if (label.empty() || eq + 1 >= arg.size())
      throw Error("--fixed '" + arg + "': expected LABEL=KNOBS, e.g. best-single=csr=8,icp=1e-4,pd=4:5:4,ir=2");
    if (configOf.count(label)) throw Error("--fixed '" + arg + "': the column '" + label + "' exists already");
    const std::string knobs = formatKnobs(parseKnobs(arg.substr(eq + 1)));  // every knob, validated
    labels.push_back(label);
    configOf[label] = writeColumnConfig(o, label, "fixed", {{"fixed", {{"knobs", knobs}}}});
  }
  for (const BenchTcSet& t : tables)
    for (double v : o.tcVelocities) {
      const std::string label = t.label(v);
      labels.push_back(label);
      configOf[label] = writeColumnConfig(
          o, label, "tc", {{"tc", {{"table", t.path}, {"reference_velocity_m_per_frame", v}}}});
    }

  std::vector<Job>& jobs = plan.jobs;
  auto& dirOf = plan.dirOf;
  auto& groundTruth = plan.groundTruth;
  for (const std::string& seq : o.sequences) {
    const std::string name = sequenceName(seq);
    groundTruth[name] = openSequence(seq)->info().groundTruthPath;
    std::vector<std::string> seqLabels = labels;
    if (!o.dseDir.empty() && fs::exists(o.dseDir + "/" + name + "/best.json")) {
      seqLabels.push_back("offline");
      configOf["offline@" + name] = writeColumnConfig(
          o, "offline@" + name, "offline",
          {{"offline", {{"result", fs::absolute(o.dseDir + "/" + name + "/best.json").string()}}}});
    }
    for (const std::string& label : seqLabels) {
      Job j;
      j.id = name + " / " + label;
      j.outDir = o.out + "/runs/" + name + "/" + label;
      const std::string config = label == "offline" ? configOf["offline@" + name] : configOf[label];
      j.runArgs = {seq, "--config", config, "--threads", std::to_string(o.threads), "--frames", std::to_string(o.frames)};
      if (o.noOdometry) j.runArgs.push_back("--no-odometry");  // else each run reads SEQ/odometry.txt
      if (!o.powerConfig.empty())
        j.runArgs.insert(j.runArgs.end(), {"--power", fs::absolute(o.powerConfig).string()});
      dirOf[{name, label}] = j.outDir;
      jobs.push_back(j);
    }
  }
  return plan;
}

// Reads every finished run (results.csv, the cells of the report); `summaries` gets each run read and
// `referenceOf` each sequence's reference trajectory.
BenchResults evaluateBench(const BenchOptions& o, BenchPlan& plan, std::vector<RunSummary>& summaries,
                           std::map<std::string, std::string>& referenceOf) {
  auto& dirOf = plan.dirOf;
  auto& groundTruth = plan.groundTruth;
  BenchResults r;
  r.outDir = o.out;
  r.columns = plan.labels;
  r.framesPerRun = o.frames;
  r.offline = !o.dseDir.empty();
  r.tcSets = plan.tables;
  r.tcVelocities = o.tcVelocities;
  for (const auto& s : o.sequences) r.sequences.push_back(sequenceName(s));
  r.plotSequence = o.plotSequence.empty() ? r.sequences.front() : o.plotSequence;
  std::vector<std::string> allLabels = plan.labels;
  if (r.offline) allLabels.push_back("offline");
  std::ofstream csv(o.out + "/results.csv");
  csv << "sequence,controller,frames,tracked_percent,computation_ms_per_frame,ate_rmse_m,reference,controller_ms_per_frame,joules_per_frame\n";
  for (const std::string& name : r.sequences) {
    const bool ownTruth = !groundTruth[name].empty();
    r.ownTruth[name] = ownTruth;
    referenceOf[name] = ownTruth ? groundTruth[name] : dirOf[{name, "accurate"}] + "/trajectory.tum";
    std::optional<Trajectory> reference;
    try {
      reference = readTumTrajectory(referenceOf[name]);
    } catch (const Error& e) {  // --report-only before the ACCURATE run finished
      std::cerr << "slambooster bench: no ATE for " << name << ": " << e.what() << "\n";
    }
    for (const std::string& label : allLabels) {
      if (!dirOf.count({name, label}) || !jobDone(dirOf[{name, label}])) continue;  // missing: listed above
      BenchCell c;
      c.present = true;
      c.dir = dirOf[{name, label}];
      // One bad summary is reported (file, key, value) and left out; the report of the rest is written.
      try {
        const RunSummary s = readSummary(c.dir);  // the types of its fields checked
        c.frames = double(s.frames);
        c.tracked = s.trackedPercent;
        c.ms = s.computationMsPerFrame;
        c.controllerMs = s.controllerMsPerFrame;
        c.joulesPerFrame = s.joulesPerFrame();  // NaN without a meter
        summaries.push_back(s);
      } catch (const Error& e) {
        std::cerr << "slambooster bench: left out " << name << " / " << label << ": " << e.what() << "\n";
        r.notes.push_back("Left out " + name + " / " + label + " (shown as -): " + e.what() + ".");
        continue;
      }
      try {
        if (!reference) throw Error("no reference trajectory");
        c.ateM = computeAte(readTumTrajectory(c.dir + "/trajectory.tum"), *reference).rmse;
      } catch (const Error& e) {
        c.ateM = NAN;
        std::cerr << "slambooster bench: no ATE for " << c.dir << ": " << e.what() << "\n";
      }
      csv << name << "," << label << "," << c.frames << "," << c.tracked << "," << c.ms << "," << c.ateM << ","
          << (ownTruth ? "groundtruth" : "accurate") << "," << c.controllerMs << "," << c.joulesPerFrame
          << "\n";  // nan without a meter, as ate_rmse_m when it cannot be computed
      r.cells[{name, label}] = c;
      // Runs from before `run` wrote its report (a resumed bench) get one now, for report.html's links.
      if (!fs::exists(c.dir + "/report.html")) try {
          writeRunReport(c.dir);
        } catch (const Error& e) {
          std::cerr << "slambooster bench: no report for " << c.dir << ": " << e.what() << "\n";
        }
    }
  }

  return r;
}

// report.md, the SVG figures and report.html of the evaluated runs.
void reportBench(const BenchOptions& o, BenchResults& r, const std::vector<RunSummary>& summaries,
                 const std::map<std::string, std::string>& referenceOf, const std::vector<std::string>& missing,
                 size_t jobCount) {
  const MachineMix machines = machineMix(summaries);
  if (!machines.kinds.empty()) r.notes.push_back(machines.note("the tables and plots"));
  if (!missing.empty())
    r.notes.push_back("Incomplete: " + std::to_string(missing.size()) + " of " + std::to_string(jobCount) +
                      " runs have not finished (shown as -): " + missingList(missing) + ".");
  const std::vector<BenchSection> sections = benchSections(r);
  const std::string md = benchMarkdown(r, sections);
  std::ofstream(o.out + "/report.md") << md;

  BenchFigures figures;
  figures.bars = {svgBenchTimeBars(r), svgBenchAteBars(r)};
  writeText(o.out + "/time.svg", figures.bars[0]);
  writeText(o.out + "/ate.svg", figures.bars[1]);
  const BenchCell traced = r.cell(r.plotSequence, "slambooster");
  if (traced.present) {
    BenchTrace trace = benchTrace(traced.dir, referenceOf.at(r.plotSequence), r.plotSequence + " / slambooster");
    for (const auto& p : trace.problems)
      std::cerr << "slambooster bench: trace of " << r.plotSequence << ": " << p << "\n";
    for (const auto& p : trace.plots) figures.trace.push_back(report::svgLinePlot(p));
    figures.traceProblems = trace.problems;
    writeText(o.out + "/trace.svg", svgStacked(trace.plots));
  }
  const std::string html = writeBenchHtml(r, sections, figures);
  std::cout << md << "\nreport in " << o.out << "/report.md and " << html << "\n";
}

void benchCommand(const BenchOptions& o) {
  BenchPlan plan = planBench(o);
  // One meter measures the whole board: runs in parallel would be charged each other's power.
  if (!o.powerConfig.empty() && o.jobs > 1)
    std::cerr << "slambooster bench: --power: running one job at a time (not " << o.jobs
              << "), so that each run's energy is its own\n";
  const int parallel = o.powerConfig.empty() ? o.jobs : 1;
  if (runMatrixPart(o.matrix, plan.jobs, parallel, o.quiet)) return;
  if (!o.matrix.reportOnly) runJobs(plan.jobs, parallel, o.quiet);
  const std::vector<std::string> missing = missingRuns(plan.jobs, "slambooster bench");

  std::vector<RunSummary> summaries;
  std::map<std::string, std::string> referenceOf;
  BenchResults r = evaluateBench(o, plan, summaries, referenceOf);
  reportBench(o, r, summaries, referenceOf, missing, plan.jobs.size());
}

}  // namespace

void addBenchCommand(CLI::App& app, const std::vector<std::string>& commandLine) {
  auto o = std::make_shared<BenchOptions>();
  auto* sub = app.add_subcommand("bench", "Run sequences x controllers and write the paper's tables and plots");
  sub->add_option("sequences", o->sequences, "Sequences (TUM layout or .raw)")->required();
  sub->add_option("--out", o->out, "Output directory (resumable: finished runs are kept)")->required();
  sub->add_option("--config", o->config, "Config (JSON): pipeline keys and a controller section for every run");
  sub->add_option("--controllers", o->controllers, "Controllers (columns)")->delimiter(',');
  sub->add_option("--dse-dir", o->dseDir, "Directory of `slambooster dse` outputs per sequence name (adds offline)");
  sub->add_option("--fixed", o->fixedColumns,
                  "LABEL=KNOBS: a column running these fixed knobs (repeatable), e.g. best-single=csr=8,icp=1e-4,ir=2");
  sub->add_option("--tc-table", o->tcTables,
                  "[NAME=]PATH: a tc configuration table from `slambooster profile` (adds the tc columns and the TC\n"
                  "table); repeat it for several profiling sets. NAME (default: the table's directory name) names\n"
                  "the set's columns tc-NAME@v; a single table given without NAME has the columns tc@v")
      ->allow_extra_args(false);
  sub->add_option("--tc-velocities", o->tcVelocities, "tc reference velocities, m/frame")->delimiter(',');
  sub->add_option("--plot-sequence", o->plotSequence, "Sequence name of the per-frame trace figure");
  sub->add_option("--frames", o->frames, "Frames per run (0 = all)");
  sub->add_option("--jobs", o->jobs, "Runs in parallel")->check(CLI::Range(1, 256));
  sub->add_option("--threads", o->threads, "Worker threads per run");
  sub->add_option("--power", o->powerConfig,
                  "Power meter config (config/power.json keys) for every run: J/frame in results.csv and the main table\n"
                  "(runs then go one at a time: one meter cannot tell parallel runs apart)");
  sub->add_flag("--no-odometry", o->noOdometry,
                "Runs ignore the sequences' odometry.txt (by default each run reads its sequence's)");
  sub->add_flag("--quiet", o->quiet, "No progress");
  addMatrixOptions(*sub, o->matrix, commandLine);
  sub->callback([o] { benchCommand(*o); });
}

}  // namespace sb::cli
