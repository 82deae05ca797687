// `slambooster summary RUN --get KEY [--get KEY ...] [--missing TEXT]`: fields of a run's summary.json for
// scripts, read through its one type (report/run_summary.h), so that no script indexes the file by key.
//
//   slambooster summary out/run --get frames --get ate.rmse_m --missing -   # "600<TAB>0.0418"
//
// KEY is a dotted path of the file ("computation_ms_per_frame", "ate.rmse_m", "moving_volume.shift_ms",
// "stage_ms_per_frame.track"). A key that is no field of the schema fails (exit 1, naming the key and the
// known ones nearby); a field of the schema that this file does not hold (no ground truth: no "ate") prints
// --missing's text, or fails without it. The values go on one line, tab-separated: numbers as JSON writes them,
// strings as they are, objects and arrays as compact JSON.

#include <algorithm>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/input_file.h"
#include "pipeline/config.h"
#include "report/run_summary.h"
#include "tools/slambooster/commands.h"

namespace sb::cli {
namespace {

using json = nlohmann::json;

struct SummaryArgs {
  std::string run;
  std::vector<std::string> keys;
  std::optional<std::string> missing;
};

// Objects whose keys are names of the data (a stage, a trigger, a state), not fields: any key below is known.
const std::set<std::string> kOpenObjects = {"stage_ms_per_frame", "triggers",       "knob_frames",
                                            "controller_frames",  "controller_sections", "tracking_state.frames",
                                            "energy.unknown_reasons"};

void addPaths(const json& j, const std::string& prefix, std::set<std::string>& out) {
  if (!prefix.empty()) out.insert(prefix);
  if (!j.is_object() || kOpenObjects.count(prefix)) return;
  for (auto it = j.begin(); it != j.end(); ++it) addPaths(*it, prefix.empty() ? it.key() : prefix + "." + it.key(), out);
}

// Every field of the schema: a summary with every optional part present, its owned sub-objects as their owners
// write them at their defaults.
std::set<std::string> schemaPaths() {
  RunSummary s;
  s.knobs.emplace();
  s.machine.emplace();
  s.daemon.emplace();
  s.ate.emplace();
  s.cpuMsPerFrame = 0.0;
  s.stopped.emplace();
  s.interrupted.emplace();
  s.meshTriangles = 0;
  s.meshSlabs = 0;
  s.complete = true;
  s.ateError = s.error = s.modelView = "x";
  s.config = configToJson(PipelineConfig{});
  s.energy.emplace();
  s.movingVolume = MovingVolumeSummary{0, 0.0, 0.0, {}, 0.0, 0.0, 0.0, 0};  // the slab counts included
  std::set<std::string> paths;
  addPaths(s.toJson(), "", paths);
  for (const auto& open : kOpenObjects) paths.insert(open);
  return paths;
}

bool known(const std::string& key, const std::set<std::string>& schema) {
  if (schema.count(key)) return true;
  for (const auto& open : kOpenObjects)
    if (key.rfind(open + ".", 0) == 0) return true;
  return false;
}

const json* find(const json& j, const std::string& key) {
  const json* at = &j;
  size_t start = 0;
  while (true) {
    const size_t dot = key.find('.', start);
    const std::string part = key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    // A name of the data may hold a dot itself (a knob setting "icp=1e-5"): the rest of the key, whole.
    if (at->is_object() && at->contains(key.substr(start))) return &(*at)[key.substr(start)];
    if (!at->is_object() || !at->contains(part)) return nullptr;
    at = &(*at)[part];
    if (dot == std::string::npos) return at->is_null() ? nullptr : at;
    start = dot + 1;
  }
}

std::string text(const json& v) { return v.is_string() ? v.get<std::string>() : v.dump(); }

void summary(const SummaryArgs& a) {
  // Typed first: a field of the wrong type fails here, naming the file and key; then printed as the type writes it.
  const json file = readRunDirSummary(a.run).toJson();
  const std::set<std::string> schema = schemaPaths();
  std::string line;
  for (size_t i = 0; i < a.keys.size(); ++i) {
    const std::string& key = a.keys[i];
    if (!known(key, schema)) {
      std::string near;
      const std::string head = key.substr(0, key.find('.'));
      for (const auto& p : schema)
        if (p.rfind(head, 0) == 0 && near.size() < 400) near += (near.empty() ? "" : ", ") + p;
      throw Error("summary: key " + quoteForMessage(key) + " is not a field of summary.json (report/run_summary.h)" +
                  (near.empty() ? std::string("") : "; fields starting alike: " + near));
    }
    const json* v = find(file, key);
    if (!v && !a.missing)
      throw Error("summary: " + quoteForMessage(a.run) + " has no " + quoteForMessage(key) +
                  " (a field this run did not write; --missing TEXT prints TEXT instead)");
    line += (i ? "\t" : "") + (v ? text(*v) : *a.missing);
  }
  std::cout << line << "\n";
}

}  // namespace

void addSummaryCommand(CLI::App& app) {
  auto args = std::make_shared<SummaryArgs>();
  auto* cmd = app.add_subcommand("summary", "Print fields of a run's summary.json (for scripts; typed, checked keys)");
  cmd->add_option("run", args->run, "Run output directory (or its summary.json)")->required();
  cmd->add_option("--get", args->keys, "Dotted key to print (repeatable; values tab-separated on one line)")
      ->required();
  cmd->add_option("--missing", args->missing, "Text printed for a field of the schema that this file does not hold");
  cmd->callback([args] { summary(*args); });
}

}  // namespace sb::cli
