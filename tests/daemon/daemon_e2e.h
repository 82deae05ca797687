#pragma once
// Shared by the slamboosterd system tests: the built binaries, a short synthetic sequence rendered once, a
// private /tmp directory for sockets, the usual daemon arguments, and readers of the outputs.

#include <sys/types.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "tests/support/files.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

namespace sb::test::e2e {

// SB_TEST_SLAMBOOSTERD, SB_TEST_SLAMBOOSTERCTL, SB_TEST_SLAMBOOSTER name other builds' binaries (testBinary).
inline const std::string kDaemon = sb::test::testBinary("SB_TEST_SLAMBOOSTERD", SB_SLAMBOOSTERD_BIN);
inline const std::string kCtl = sb::test::testBinary("SB_TEST_SLAMBOOSTERCTL", SB_SLAMBOOSTERCTL_BIN);
inline const std::string kTool = sb::test::testBinary("SB_TEST_SLAMBOOSTER", SB_SLAMBOOSTER_BIN);
inline constexpr int kFrames = 30;

// A short synthetic sequence (320x240, csr 2, 64^3 volume: a few tens of ms per frame), rendered once per
// test program (SB_E2E_SCRATCH names its directory, so that programs run in parallel do not share one).
struct Fixture {
  std::string dir, sequence, pipelineConfig;
  Fixture() {
    dir = sb::test::scratchDir(SB_E2E_SCRATCH);
    sequence = dir + "/seq";
    const auto synth = sb::test::runCommand(kTool + " synth --out " + sequence + " --builtin-frames " +
                                            std::to_string(kFrames) +
                                            " --width 320 --height 240 --fx 240 --fy 240 --threads 1");
    if (synth.exitCode != 0) throw std::runtime_error("synth failed: " + synth.output);
    pipelineConfig = dir + "/pipeline.json";
    std::ofstream(pipelineConfig) << R"({"volume_resolution": 64, "knobs": "csr=2,ir=1"})";
  }
};

inline const Fixture& fixture() {
  static const Fixture f;
  return f;
}

// A private /tmp directory for one test's socket (socket paths must stay short).
struct TempDir {
  std::string path;
  TempDir() {
    char t[] = "/tmp/sbd-e2e-XXXXXX";
    if (!mkdtemp(t)) throw std::runtime_error("mkdtemp");
    path = t;
  }
  ~TempDir() { std::filesystem::remove_all(path); }
};

inline std::vector<std::string> daemonArgs(const std::string& socket, const std::string& out,
                                           const std::string& pacing, const std::string& atEnd) {
  return {kDaemon,
          "--input",
          fixture().sequence,
          "--out",
          out,
          "--socket",
          socket,
          "--pacing",
          pacing,
          "--at-end",
          atEnd,
          "--set",
          "slam.pipeline_config=" + fixture().pipelineConfig,
          "--controller",
          "fixed"};
}

using sb::test::dataLines;

inline std::set<std::string> trajectoryTimestamps(const std::string& path) {
  std::ifstream in(path);
  std::set<std::string> stamps;
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] != '#') stamps.insert(line.substr(0, line.find(' ')));
  return stamps;
}

// The pass-NNNN directories of a looping replay in `out`, by number.
inline std::vector<int> passDirectories(const std::string& out) {
  std::vector<int> passes;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(out, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("pass-", 0) == 0) passes.push_back(std::stoi(name.substr(5)));
  }
  std::sort(passes.begin(), passes.end());
  return passes;
}

inline std::string passDirectory(const std::string& out, int n) {
  char name[32];
  std::snprintf(name, sizeof name, "/pass-%04d", n);
  return out + name;
}

inline nlohmann::json ctlJson(const std::string& socket, const std::string& args) {
  const auto r = sb::test::runCommand(kCtl + " --json --socket " + socket + " " + args);
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  return nlohmann::json::parse(r.output.substr(0, r.output.find('\n')));
}

}  // namespace sb::test::e2e
