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
#include "report/run_summary.h"
#include "tools/slambooster/commands.h"

namespace sb::cli {
namespace {

struct CompareArgs {
  std::string run, against;
};

RunSummary readSummary(const std::string& dir) {
  return readRunDirSummary(dir, "is " + quoteForMessage(dir) + " a finished run's output directory?");
}

// "ATE 4.17 cm" or "no ground truth".
std::string ateText(const RunSummary& s) {
  if (s.ate) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "ATE %.2f cm", s.ate->rmseM * 100.0);
    return buf;
  }
  return "no ground truth";
}

// The run's controller (both front ends write it since schema 1); in an older daemon summary, the one that
// decided the most frames.
std::string name(const RunSummary& s) {
  if (!s.controller.empty()) return s.controller;
  std::string best = "run";
  size_t most = 0;
  for (const auto& [controller, frames] : s.controllerFrames)
    if (frames > most) {
      most = frames;
      best = controller;
    }
  return best;
}

void compare(const CompareArgs& a) {
  const RunSummary run = readSummary(a.run);
  const double ms = run.computationMsPerFrame;
  std::printf("%s: %zu frames, %.1f%% tracked, %s, %.1f ms/frame", name(run).c_str(), run.frames,
              run.trackedPercent, ateText(run).c_str(), ms);
  if (!a.against.empty()) {
    const RunSummary base = readSummary(a.against);
    const double baseMs = base.computationMsPerFrame;
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
