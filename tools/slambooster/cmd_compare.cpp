// `slambooster compare RUN [--against BASE]`: one line a newcomer can read about a finished run (frames,
// % tracked, ATE when the sequence has ground truth, ms/frame) and how it compares with another run on the
// same input (the main job compares the daemon's adaptive run with DEFAULT).

#include <cstdio>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "core/config_reader.h"
#include "core/error.h"
#include "core/input_file.h"
#include "tools/slambooster/commands.h"

namespace sb::cli {
namespace {

struct CompareArgs {
  std::string run, against;
};

nlohmann::json readSummary(const std::string& dir) {
  const std::string path = dir + "/summary.json";
  const std::string problem = pathProblem(path);
  if (!problem.empty())
    throw Error("run summary " + quoteForMessage(path) + " " + problem + ": is " + quoteForMessage(dir) +
                " a finished run's output directory?");
  return readJsonConfig(path, "run summary");  // bounded nesting, line and column, objects only
}

double number(const nlohmann::json& j, const char* key, const std::string& dir) {
  if (!j.contains(key) || !j.at(key).is_number())
    throw Error("'" + dir + "/summary.json' has no number '" + key + "'");
  return j.at(key).get<double>();
}

// "ATE 4.17 cm" or "no ground truth".
std::string ateText(const nlohmann::json& s) {
  if (s.contains("ate") && s.at("ate").contains("rmse_m")) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "ATE %.2f cm", s.at("ate").at("rmse_m").get<double>() * 100.0);
    return buf;
  }
  return "no ground truth";
}

// The run's controller: "controller" (slambooster run), else the one that decided the most frames (daemon).
std::string name(const nlohmann::json& s) {
  if (s.contains("controller") && s.at("controller").is_string()) return s.at("controller").get<std::string>();
  std::string best = "run";
  size_t most = 0;
  if (s.contains("controller_frames") && s.at("controller_frames").is_object())
    for (auto it = s.at("controller_frames").begin(); it != s.at("controller_frames").end(); ++it)
      if (it->is_number_unsigned() && it->get<size_t>() > most) {
        most = it->get<size_t>();
        best = it.key();
      }
  return best;
}

void compare(const CompareArgs& a) {
  const nlohmann::json run = readSummary(a.run);
  const double ms = number(run, "computation_ms_per_frame", a.run);
  std::printf("%s: %.0f frames, %.1f%% tracked, %s, %.1f ms/frame", name(run).c_str(), number(run, "frames", a.run),
              number(run, "tracked_percent", a.run), ateText(run).c_str(), ms);
  if (!a.against.empty()) {
    const nlohmann::json base = readSummary(a.against);
    const double baseMs = number(base, "computation_ms_per_frame", a.against);
    std::printf("; %s on the same input: %s, %.1f ms/frame", name(base).c_str(), ateText(base).c_str(), baseMs);
    if (baseMs > 0) {
      const double cut = 100.0 * (1.0 - ms / baseMs);
      std::printf(" (%s takes %.0f%% %s time)", name(run).c_str(), cut >= 0 ? cut : -cut, cut >= 0 ? "less" : "more");
    }
  }
  std::printf("\n");
}

}  // namespace

void addCompareCommand(CLI::App& app) {
  auto args = std::make_shared<CompareArgs>();
  CLI::App* sub = app.add_subcommand("compare", "One line about a finished run, and how it compares with another");
  sub->add_option("run", args->run, "Output directory of a run (slambooster run, bench, or the daemon)")->required();
  sub->add_option("--against", args->against, "Another run's output directory on the same input (e.g. DEFAULT)");
  sub->callback([args] { compare(*args); });
}

}  // namespace sb::cli
