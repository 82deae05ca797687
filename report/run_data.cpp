#include "report/run_data.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "core/config_reader.h"
#include "core/error.h"
#include "core/input_file.h"
#include "core/rotating_file.h"
#include "report/nav_files.h"

namespace sb::report {

namespace fs = std::filesystem;

namespace {

bool isFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

// The file of per-frame stream `name` the report reads: DIR/NAME, or with rotated outputs (a live session)
// only its newest segment, so that the report's memory and time stay bounded however long the pass ran (the
// summary covers the whole pass). Empty when the stream has no file.
fs::path streamFile(RunData& run, const std::string& name) {
  const std::vector<std::string> files = streamFiles(run.dir, name);
  if (files.empty()) return (fs::path(run.dir) / name);
  if (files.size() > 1 || files.back() != (fs::path(run.dir) / name).string())
    run.notes.push_back("rotated outputs: the per-frame plots read " +
                        fs::path(files.back()).filename().string() + ", the newest of " +
                        std::to_string(files.size()) + " segments of " + name +
                        " on disk; summary.json covers the whole pass");
  return files.back();
}

void loadSummary(RunData& run) {
  const fs::path path = fs::path(run.dir) / "summary.json";
  if (!isFile(path)) {
    run.problems.push_back("'" + path.string() + "' is missing (no summary table; the run may not have finished)");
    return;
  }
  try {
    run.summary = readRunSummary(path.string());  // bounded nesting, line and column, typed fields
    run.summaryJson = readJsonConfig(path.string(), "run summary");  // the keys the type does not know too
  } catch (const std::exception& e) {
    run.problems.push_back(std::string(e.what()) + " (no summary table)");
  }
}

// The ground truth: the explicit path, else groundtruth.txt in the summary's sequence directory.
// energy.jsonl (written by `slambooster run --power` and the daemon; lines resolve later than their frames):
// its joules and mean power go into the frame log's columns for the frames it names. Damaged lines are
// problems, not failures.
void mergeEnergyLog(RunData& run, const fs::path& path) {
  std::unique_ptr<InputFile> file;
  try {
    file = std::make_unique<InputFile>(path.string(), "energy log");
  } catch (const Error& e) {
    run.problems.push_back(e.what());
    return;
  }
  std::istream& in = *file;
  std::map<int64_t, std::pair<double, double>> energy;  // frame -> joules, mean W (NaN when unknown)
  size_t lineNumber = 0, bad = 0;
  for (std::string line; std::getline(in, line);) {
    ++lineNumber;
    if (line.empty()) continue;
    const nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("frame") || !j["frame"].is_number_integer()) {
      if (bad++ == 0) run.problems.push_back("'" + path.string() + "' line " + std::to_string(lineNumber) + " is not an energy record");
      continue;
    }
    const auto num = [&](const char* key) {
      return j.contains(key) && j[key].is_number() ? j[key].get<double>() : std::nan("");
    };
    energy[j["frame"].get<int64_t>()] = {num("joules"), num("mean_watts")};
  }
  FrameLog& f = run.frames;
  for (size_t i = 0; i < f.frame.size(); ++i) {
    const auto it = energy.find(static_cast<int64_t>(f.frame[i]));
    if (it == energy.end()) continue;
    if (i < f.joules.size()) f.joules[i] = it->second.first;
    if (i < f.powerW.size()) f.powerW[i] = it->second.second;
  }
}

void findGroundTruth(RunData& run, const RunLoadOptions& options) {
  std::string path = options.groundTruth;
  if (path.empty()) {
    if (!run.summary || run.summary->sequence.empty()) {
      run.notes.push_back("no ground truth: summary.json names no sequence (pass --groundtruth FILE)");
      return;
    }
    const fs::path candidate = fs::path(run.summary->sequence) / "groundtruth.txt";
    if (!isFile(candidate)) {
      run.notes.push_back("no ground truth: '" + candidate.string() +
                          "' does not exist (pass --groundtruth FILE; relative sequence paths are read from the "
                          "current directory)");
      return;
    }
    path = candidate.string();
  }
  try {
    run.groundTruth = readTumTrajectory(path);
    run.groundTruthPath = path;
  } catch (const Error& e) {
    run.problems.push_back(std::string("ground truth not used: ") + e.what());
    return;
  }
  if (run.trajectory.empty()) return;
  try {
    run.ate = computeAte(run.trajectory, run.groundTruth);
  } catch (const Error& e) {
    run.problems.push_back("trajectory not compared with the ground truth '" + path + "': " + e.what());
  }
}

}  // namespace

RunData loadRun(const std::string& dir, const RunLoadOptions& options) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw Error("run directory '" + dir + "' does not exist (give the --out directory of `slambooster run`)");
  RunData run;
  run.dir = dir;
  run.label = fs::path(dir).lexically_normal().filename().string();
  if (run.label.empty() || run.label == ".") run.label = fs::absolute(dir, ec).lexically_normal().parent_path().filename().string();
  const fs::path base(dir);
  bool any = false;
  for (const char* f : {"summary.json", "frames.jsonl", "trajectory.tum", "model.png"}) any |= isFile(base / f);
  any |= !streamFiles(dir, "frames.jsonl").empty() || !streamFiles(dir, "trajectory.tum").empty();
  if (!any)
    throw Error("'" + dir + "' holds none of summary.json, frames.jsonl, trajectory.tum, model.png: is it the --out "
                "directory of `slambooster run`?");

  loadSummary(run);
  const fs::path framesFile = streamFile(run, "frames.jsonl");
  if (isFile(framesFile)) {
    FrameLogReadResult log = readFrameLog(framesFile.string());
    run.frames = std::move(log.log);
    run.problems.insert(run.problems.end(), log.problems.begin(), log.problems.end());
  } else {
    run.problems.push_back("'" + framesFile.string() + "' is missing (no per-frame plots)");
  }
  const fs::path energyFile = streamFile(run, "energy.jsonl");
  if (isFile(energyFile)) mergeEnergyLog(run, energyFile);
  const fs::path trajectoryFile = streamFile(run, "trajectory.tum");
  if (isFile(trajectoryFile)) {
    try {
      run.trajectory = readTumTrajectory(trajectoryFile.string());
    } catch (const Error& e) {
      run.problems.push_back(std::string("trajectory not shown: ") + e.what());
    }
  } else {
    run.problems.push_back("'" + trajectoryFile.string() + "' is missing (no trajectory plot)");
  }
  findGroundTruth(run, options);
  if (isFile(base / "model.png"))
    run.modelPath = (base / "model.png").string();
  else
    run.problems.push_back("'" + (base / "model.png").string() + "' is missing (no map image)");
  if (isFile(base / "mesh.ply")) run.meshPath = (base / "mesh.ply").string();
  loadWheels(run);
  loadGrid(run);
  return run;
}

}  // namespace sb::report
