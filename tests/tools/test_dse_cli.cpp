// `slambooster dse` end to end: the out-of-bound rules, branch-and-bound pruning, and several dse processes
// sharing one output directory.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "tests/support/files.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

namespace fs = std::filesystem;
using sb::test::readJson;
using sb::test::readText;
using sb::test::runCommand;

namespace {

const std::string kTool = SB_SLAMBOOSTER_BIN;

// A 6-frame synthetic sequence and a 64^3 volume config in `dir`; returns the dse command line's start.
std::string smallDse(const std::string& dir) {
  REQUIRE(runCommand(kTool + " synth --out " + dir + "/seq --builtin-frames 6 --no-noise").exitCode == 0);
  std::ofstream(dir + "/small.json") << R"({"volume_resolution": 64})";
  return kTool + " dse " + dir + "/seq --out " + dir + "/dse --config " + dir + "/small.json";
}

// A finished csr=8 run within the bound whose 6 frames took 6e-6 ms in all, as another process would leave it.
void writeFastRun(const std::string& runDir) {
  fs::create_directories(runDir);
  std::ofstream(runDir + "/summary.json.tmp") << R"({"complete": true, "frames": 6, "tracked_percent": 100.0,
      "computation_ms_per_frame": 1e-6, "ate": {"rmse_m": 0.001}})";
  fs::rename(runDir + "/summary.json.tmp", runDir + "/summary.json");
}

const char* const kFastId = "csr8_icp1e-05_pd4-5-4_tr1_ir1";
const char* const kSlowId = "csr4_icp1e-05_pd4-5-4_tr1_ir1";

}  // namespace

TEST_CASE("dse stops a run once it is slower than the fastest setting within the bound, and --no-prune does not",
          "[tools][system]") {
  const std::string dir = sb::test::scratchDir("cli_dse_prune");
  // Any real run is slower than the fast run's 6e-6 ms after its first frame, so the csr=4 run stops there.
  writeFastRun(dir + "/dse/runs/" + kFastId);
  const std::string dse = smallDse(dir) + " --csr 4,8 --icp 1e-5 --pd0 4 --max-ate 1.0 --quiet";
  const auto pruned = runCommand(dse);
  INFO(pruned.output);
  REQUIRE(pruned.exitCode == 0);
  CHECK_THAT(pruned.output, Catch::Contains("1 of 2 settings stopped early"));
  const auto slow = readJson(dir + "/dse/runs/" + kSlowId + "/summary.json");
  CHECK(slow.at("frames") == 1);
  CHECK(slow.at("stopped").at("at_frame") == 1);
  CHECK(slow.at("stopped").at("limit_ms").get<double>() == Approx(6e-6));
  auto best = readJson(dir + "/dse/best.json");
  CHECK(best.at("stopped_early") == 1);
  CHECK(best.at("best").at("knobs").get<std::string>().rfind("csr=8", 0) == 0);
  const std::string csv = readText(dir + "/dse/results.csv");
  CHECK_THAT(csv, Catch::Contains(",within_bound,stopped_at_frame\n"));
  CHECK_THAT(csv, Catch::Contains(",nan,0,1\n"));  // the stopped csr=4 run: no ATE, out of bound, frame 1
  // Every row has the header's 7 fields: the knobs text holds commas, so it is quoted.
  std::istringstream lines(csv);
  size_t rows = 0;
  for (std::string line; std::getline(lines, line); ++rows) {
    size_t fields = 1;
    bool quoted = false;
    for (char c : line) {
      if (c == '"') quoted = !quoted;
      fields += c == ',' && !quoted;
    }
    INFO(line);
    CHECK(fields == 7);
  }
  CHECK(rows == 3);

  // --no-prune runs the stopped setting again, to the end.
  const auto full = runCommand(dse + " --no-prune");
  INFO(full.output);
  REQUIRE(full.exitCode == 0);
  CHECK_THAT(full.output, !Catch::Contains("stopped early"));
  const auto whole = readJson(dir + "/dse/runs/" + kSlowId + "/summary.json");
  CHECK(whole.at("frames") == 6);
  CHECK_FALSE(whole.contains("stopped"));
  CHECK(readJson(dir + "/dse/best.json").at("stopped_early") == 0);
}

TEST_CASE("dse and profile treat a run whose ATE is undefined as out of bound", "[tools][system]") {
  const std::string dir = sb::test::scratchDir("cli_dse_static");
  // A camera that never moves: ground truth exists, but ATE alignment is undefined for every run.
  {
    std::ofstream tum(dir + "/static.tum");
    for (int i = 0; i < 4; ++i) tum << i / 30.0 << " 0 -0.1 -1.2 0 0.7071068 0 0.7071068\n";
  }
  const std::string seq = dir + "/seq";
  REQUIRE(runCommand(kTool + " synth --out " + seq + " --trajectory " + dir + "/static.tum --no-noise").exitCode == 0);
  std::ofstream(dir + "/small.json") << R"({"volume_resolution": 64})";
  const auto dse = runCommand(kTool + " dse " + seq + " --out " + dir + "/dse --config " + dir +
                              "/small.json --csr 8 --icp 1e-5 --pd0 4 --quiet");
  INFO(dse.output);
  REQUIRE(dse.exitCode == 0);
  CHECK_THAT(dse.output, Catch::Contains("no setting keeps"));
  CHECK(readJson(dir + "/dse/best.json").at("best").is_null());
  std::ifstream csv(dir + "/dse/results.csv");
  std::string header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  CHECK_THAT(row, Catch::Contains(",nan,0"));

  const auto profile = runCommand(kTool + " profile " + seq + " --out " + dir + "/profile --config " + dir +
                                  "/small.json --csr 8 --icp 1e-5 --pd0 4 --ir 1 --quiet");
  CHECK(profile.exitCode == 1);
  CHECK_THAT(profile.output, Catch::Contains("no setting has a defined ATE"));
}

TEST_CASE("dse waits for the runs another dse process holds, and takes over those whose process is gone",
          "[tools][system]") {
  const std::string dir = sb::test::scratchDir("cli_dse_shared");
  const std::string dse = smallDse(dir) + " --csr 4,8 --icp 1e-5 --pd0 4 --max-ate 1.0";
  // Another live process (this test) holds the csr=8 run; it finishes only after this dse has run csr=4.
  const std::string held = dir + "/dse/runs/" + kFastId;
  fs::create_directories(held);
  char host[256] = {};
  gethostname(host, sizeof(host) - 1);
  std::ofstream(held + "/.claim") << host << " " << getpid() << "\n";
  sb::test::CommandResult shared;
  std::thread other([&] { shared = runCommand(dse); });
  const std::string own = dir + "/dse/runs/" + kSlowId + "/summary.json";
  for (int i = 0; i < 600 && !(fs::exists(own) && readText(own).find("\"complete\": true") != std::string::npos); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // before the fix, dse had failed by now
  writeFastRun(held);
  fs::remove(held + "/.claim");
  other.join();
  INFO(shared.output);
  REQUIRE(shared.exitCode == 0);
  CHECK_THAT(shared.output, Catch::Contains("waiting for 1 runs that another process is running"));
  CHECK(readJson(dir + "/dse/best.json").at("best").at("knobs").get<std::string>().rfind("csr=8", 0) == 0);

  // A claim whose process is gone is taken over: the run is redone by this dse.
  fs::remove(held + "/summary.json");
  std::ofstream(held + "/.claim") << host << " 999999999\n";  // above any pid_max: no such process
  const auto takeover = runCommand(dse + " --no-prune");
  INFO(takeover.output);
  REQUIRE(takeover.exitCode == 0);
  CHECK(readJson(held + "/summary.json").at("frames") == 6);
  CHECK_FALSE(fs::exists(held + "/.claim"));
}
