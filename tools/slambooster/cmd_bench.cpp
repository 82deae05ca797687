// `slambooster bench SEQ...`: the paper's experiments as one command. Runs every sequence under every
// controller (resumable, --jobs runs in parallel, progress on stderr), evaluates each trajectory against the
// sequence's ground truth (or, without one, the ACCURATE run's trajectory, as in the paper) and writes
// report.md (main table DEFAULT vs SLAMBooster with the geometric mean, the incremental study, PID vs step,
// online vs offline, the TC table), results.csv, and SVG plots (time and ATE bars, the per-frame trace).

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

#include "core/error.h"
#include "core/trajectory.h"
#include "drivers/sequence.h"
#include "eval/trajectory_eval.h"
#include "tools/slambooster/bench_plots.h"
#include "tools/slambooster/commands.h"
#include "tools/slambooster/run_jobs.h"

namespace sb::cli {

namespace {

namespace fs = std::filesystem;

struct BenchOptions {
  std::vector<std::string> sequences;
  std::string out, config, dseDir, tcTable, plotSequence;
  std::vector<std::string> controllers{"default", "accurate", "pid", "pid+surface", "pid+surface+correction",
                                       "slambooster", "step"};
  std::vector<double> tcVelocities{0.005, 0.01, 0.02};
  size_t frames = 0;
  int jobs = 1;
  unsigned threads = 1;
  bool quiet = false;
};

struct Cell {
  bool present = false;
  double frames = 0, tracked = 0, ms = 0, ateM = NAN, controllerMs = 0;
  std::string dir;
};

nlohmann::json readJsonFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error("cannot open '" + path + "'");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw Error("'" + path + "' is not valid JSON: " + e.what());
  }
}

// The config file of one bench column: the user's config with the controller section's name (and extra
// section keys) set.
std::string writeColumnConfig(const BenchOptions& o, const std::string& label, const std::string& name,
                              const nlohmann::json& sectionPatch) {
  nlohmann::json j = o.config.empty() ? nlohmann::json::object() : readJsonFile(o.config);
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
  std::ofstream(path) << j.dump(2) << "\n";
  return path;
}

std::string cm(double m) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(2) << m * 100;
  return std::isfinite(m) ? s.str() : "-";
}
std::string num(double v, int precision = 1) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(precision) << v;
  return s.str();
}

void benchCommand(const BenchOptions& o) {
  // Columns: label -> (controller name, config file).
  std::vector<std::string> labels = o.controllers;
  if (std::find(labels.begin(), labels.end(), "accurate") == labels.end()) labels.push_back("accurate");
  std::map<std::string, std::string> configOf;
  for (const std::string& c : labels) configOf[c] = writeColumnConfig(o, c, c, nlohmann::json::object());
  if (!o.tcTable.empty())
    for (double v : o.tcVelocities) {
      const std::string label = "tc@" + num(v, 3);
      labels.push_back(label);
      configOf[label] = writeColumnConfig(
          o, label, "tc", {{"tc", {{"table", fs::absolute(o.tcTable).string()}, {"reference_velocity_m_per_frame", v}}}});
    }

  std::vector<Job> jobs;
  std::map<std::pair<std::string, std::string>, std::string> dirOf;
  std::map<std::string, std::string> groundTruth;
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
      dirOf[{name, label}] = j.outDir;
      jobs.push_back(j);
    }
  }
  runJobs(jobs, o.jobs, o.quiet);

  // Evaluate every run.
  std::vector<std::string> names;
  for (const auto& s : o.sequences) names.push_back(sequenceName(s));
  std::vector<std::string> allLabels = labels;
  if (!o.dseDir.empty()) allLabels.push_back("offline");
  std::map<std::pair<std::string, std::string>, Cell> cells;
  std::ofstream csv(o.out + "/results.csv");
  csv << "sequence,controller,frames,tracked_percent,computation_ms_per_frame,ate_rmse_m,reference,controller_ms_per_frame\n";
  for (const std::string& name : names) {
    const bool ownTruth = !groundTruth[name].empty();
    const std::string refPath = ownTruth ? groundTruth[name] : dirOf[{name, "accurate"}] + "/trajectory.tum";
    const Trajectory reference = readTumTrajectory(refPath);
    for (const std::string& label : allLabels) {
      if (!dirOf.count({name, label})) continue;
      Cell c;
      c.present = true;
      c.dir = dirOf[{name, label}];
      const nlohmann::json s = readSummary(c.dir);
      c.frames = s["frames"];
      c.tracked = s["tracked_percent"];
      c.ms = s["computation_ms_per_frame"];
      c.controllerMs = s.value("controller_ms_per_frame", 0.0);
      try {
        c.ateM = computeAte(readTumTrajectory(c.dir + "/trajectory.tum"), reference).rmse;
      } catch (const Error&) {
        c.ateM = NAN;
      }
      csv << name << "," << label << "," << c.frames << "," << c.tracked << "," << c.ms << "," << c.ateM << ","
          << (ownTruth ? "groundtruth" : "accurate") << "," << c.controllerMs << "\n";
      cells[{name, label}] = c;
    }
  }

  // report.md
  std::ostringstream md;
  md << "# slambooster bench\n\nSequences: " << names.size() << "; frames per run: "
     << (o.frames ? std::to_string(o.frames) : std::string("all")) << "; computation = preprocessing + tracking + "
     << "integration + raycast (ms/frame, host clock); ATE RMSE in cm against the ground truth, or against the "
     << "ACCURATE run where a sequence has none (marked *).\n\n";
  md << "## DEFAULT vs SLAMBooster\n\n| sequence | frames | DEFAULT tracked % | DEFAULT ms/frame | DEFAULT ATE cm | "
        "SLAMBooster tracked % | SLAMBooster ms/frame | SLAMBooster ATE cm | time cut % |\n|---|---|---|---|---|---|---|---|---|\n";
  double logRatio = 0, cutSum = 0;
  int paired = 0, violations = 0;
  for (const std::string& name : names) {
    const Cell d = cells[{name, "default"}], b = cells[{name, "slambooster"}];
    if (!d.present || !b.present) continue;
    const double cut = 100.0 * (1.0 - b.ms / d.ms);
    logRatio += std::log(b.ms / d.ms);
    cutSum += cut;
    ++paired;
    violations += !(b.ateM < 0.05) || b.tracked < 99.0;
    md << "| " << name << (groundTruth[name].empty() ? "*" : "") << " | " << b.frames << " | " << num(d.tracked) << " | "
       << num(d.ms) << " | " << cm(d.ateM) << " | " << num(b.tracked) << " | " << num(b.ms) << " | " << cm(b.ateM)
       << " | " << num(cut) << " |\n";
  }
  if (paired) {
    const double geoCut = 100.0 * (1.0 - std::exp(logRatio / paired));
    md << "| **geomean** | | | | | | | | **" << num(geoCut) << "** |\n\nMean computation-time cut of SLAMBooster vs "
       << "DEFAULT: " << num(cutSum / paired) << "% (arithmetic mean of per-sequence cuts), " << num(geoCut)
       << "% (geometric mean of time ratios); sequences with ATE >= 5 cm or < 99% tracked under SLAMBooster: "
       << violations << " of " << paired << ".\n\n";
  }
  const auto study = [&](const std::string& title, const std::vector<std::string>& cols) {
    md << "## " << title << "\n\nms/frame / ATE cm\n\n| sequence |";
    for (const auto& c : cols) md << " " << c << " |";
    md << "\n|---|";
    for (size_t i = 0; i < cols.size(); ++i) md << "---|";
    md << "\n";
    for (const std::string& name : names) {
      md << "| " << name << " |";
      for (const auto& c : cols) {
        const Cell x = cells[{name, c}];
        md << " " << (x.present ? num(x.ms) + " / " + cm(x.ateM) : "-") << " |";
      }
      md << "\n";
    }
    md << "\n";
  };
  study("Incremental study", {"default", "pid", "pid+surface", "pid+surface+correction", "slambooster"});
  study("PID vs step", {"default", "pid", "step", "slambooster"});
  if (!o.dseDir.empty()) study("Online vs offline best (dse)", {"default", "offline", "slambooster"});
  if (!o.tcTable.empty()) {
    md << "## TC (application-agnostic) vs SLAMBooster\n\nTable: `" << o.tcTable << "`\n\n| v_ref m/frame | error "
          "violations (ATE >= 5 cm) | better time than SLAMBooster |\n|---|---|---|\n";
    for (double v : o.tcVelocities) {
      const std::string label = "tc@" + num(v, 3);
      int bad = 0, faster = 0;
      for (const std::string& name : names) {
        const Cell t = cells[{name, label}], b = cells[{name, "slambooster"}];
        bad += t.present && !(t.ateM < 0.05);
        faster += t.present && b.present && t.ms < b.ms;
      }
      md << "| " << num(v, 3) << " | " << bad << " of " << names.size() << " | " << faster << " of " << names.size()
         << " |\n";
    }
    md << "\n";
  }
  md << "Controller overhead (slambooster): ";
  for (const std::string& name : names) {
    const Cell b = cells[{name, "slambooster"}];
    if (b.present) md << name << " " << num(100.0 * b.controllerMs / std::max(b.ms, 1e-9), 3) << "% ";
  }
  md << "of frame time.\n\nPlots: time.svg, ate.svg, trace.svg. Raw numbers: results.csv.\n";
  std::ofstream(o.out + "/report.md") << md.str();

  // Plots.
  BarChart time{"computation time per frame", "ms/frame", names, labels, {}, 0.0};
  BarChart ate{"ATE RMSE", "cm", names, labels, {}, 5.0};
  for (const std::string& name : names) {
    std::vector<double> t, a;
    for (const std::string& label : labels) {
      const Cell c = cells[{name, label}];
      t.push_back(c.present ? c.ms : NAN);
      a.push_back(c.present ? c.ateM * 100 : NAN);
    }
    time.values.push_back(t);
    ate.values.push_back(a);
  }
  writeBarChart(o.out + "/time.svg", time);
  writeBarChart(o.out + "/ate.svg", ate);
  const std::string plotName = o.plotSequence.empty() ? names.front() : o.plotSequence;
  if (cells[{plotName, "slambooster"}].present) {
    const std::string dir = cells[{plotName, "slambooster"}].dir;
    FrameTrace trace;
    trace.title = plotName + " under slambooster: per-frame error, csr, triggers";
    const std::string refPath =
        groundTruth[plotName].empty() ? dirOf[{plotName, "accurate"}] + "/trajectory.tum" : groundTruth[plotName];
    // A run whose trajectory cannot be aligned (lost from the first frame: every position the same) still gets
    // its knob and trigger trace; its ATE is already n/a in the tables.
    try {
      const AteResult r = computeAte(readTumTrajectory(dir + "/trajectory.tum"), readTumTrajectory(refPath));
      for (double e : r.errors) trace.iteCm.push_back(e * 100);
    } catch (const Error& e) {
      std::cerr << "slambooster bench: " << plotName << " / slambooster: no per-frame error in trace.svg: " << e.what()
                << "\n";
    }
    trace.triggerNames = {"integral", "derivative_up", "derivative_down", "surface", "correction", "hold"};
    trace.triggers.assign(trace.triggerNames.size(), {});
    std::ifstream log(dir + "/frames.jsonl");
    for (std::string line; std::getline(log, line);) {
      const auto f = nlohmann::json::parse(line);
      trace.csr.push_back(f["knobs"]["csr"]);
      const auto fired = f["triggers"].get<std::vector<std::string>>();
      for (size_t k = 0; k < trace.triggerNames.size(); ++k)
        trace.triggers[k].push_back(std::find(fired.begin(), fired.end(), trace.triggerNames[k]) != fired.end());
    }
    writeTraceFigure(o.out + "/trace.svg", trace);
  }
  std::cout << md.str() << "\nreport in " << o.out << "/report.md\n";
}

}  // namespace

void addBenchCommand(CLI::App& app) {
  auto o = std::make_shared<BenchOptions>();
  auto* sub = app.add_subcommand("bench", "Run sequences x controllers and write the paper's tables and plots");
  sub->add_option("sequences", o->sequences, "Sequences (TUM layout or .raw)")->required();
  sub->add_option("--out", o->out, "Output directory (resumable: finished runs are kept)")->required();
  sub->add_option("--config", o->config, "Config (JSON): pipeline keys and a controller section for every run");
  sub->add_option("--controllers", o->controllers, "Controllers (columns)")->delimiter(',');
  sub->add_option("--dse-dir", o->dseDir, "Directory of `slambooster dse` outputs per sequence name (adds offline)");
  sub->add_option("--tc-table", o->tcTable, "tc configuration table from `slambooster profile` (adds tc columns)");
  sub->add_option("--tc-velocities", o->tcVelocities, "tc reference velocities, m/frame")->delimiter(',');
  sub->add_option("--plot-sequence", o->plotSequence, "Sequence name of the per-frame trace figure");
  sub->add_option("--frames", o->frames, "Frames per run (0 = all)");
  sub->add_option("--jobs", o->jobs, "Runs in parallel")->check(CLI::Range(1, 256));
  sub->add_option("--threads", o->threads, "Worker threads per run");
  sub->add_flag("--quiet", o->quiet, "No progress");
  sub->callback([o] { benchCommand(*o); });
}

}  // namespace sb::cli
