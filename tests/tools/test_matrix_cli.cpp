// The matrix commands past one process (matrix_plan.h, claim.h): --plan writes one self-contained command
// per run, --run-index and --shard run exactly their runs, --report-only runs nothing and lists what is
// missing, every summary says where it ran and a report that mixes machines says so, and a claim from
// another host is respected while its heartbeat goes on and taken over once it stops.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/files.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

namespace fs = std::filesystem;
using sb::test::readJson;
using sb::test::readText;
using sb::test::runCommand;

namespace {

const std::string kTool = SB_SLAMBOOSTER_BIN;

// A 4-frame synthetic sequence and a small volume in `dir`; returns the bench command of a 2-run matrix
// (DEFAULT and ACCURATE) into dir/bench.
std::string smallBench(const std::string& dir) {
  REQUIRE(runCommand(kTool + " synth --out " + dir + "/seq --builtin-frames 4 --no-noise --width 160 --height 120 "
                             "--fx 131 --fy 131").exitCode == 0);
  std::ofstream(dir + "/small.json") << R"({"volume_resolution": 64})";
  return kTool + " bench " + dir + "/seq --out " + dir + "/bench --config " + dir +
         "/small.json --controllers default --threads 1";
}

std::vector<std::string> lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> all;
  for (std::string line; std::getline(in, line);) all.push_back(line);
  return all;
}

bool complete(const std::string& runDir) {
  return fs::exists(runDir + "/summary.json") && readJson(runDir + "/summary.json").value("complete", false);
}

std::string hostName() {
  char host[256] = {};
  gethostname(host, sizeof(host) - 1);
  return host;
}

}  // namespace

TEST_CASE("bench --plan, --run-index, --shard and --report-only split the matrix and report what finished",
          "[tools][system]") {
  const std::string dir = sb::test::scratchDir("cli_matrix_plan");
  const std::string bench = smallBench(dir);
  const std::string runs = dir + "/bench/runs/seq/";

  const auto plan = runCommand(bench + " --plan " + dir + "/plan.txt");
  INFO(plan.output);
  REQUIRE(plan.exitCode == 0);
  CHECK_THAT(plan.output, Catch::Contains("2 runs in " + dir + "/plan.txt"));
  CHECK_THAT(plan.output, Catch::Contains("--report-only"));
  const std::vector<std::string> planned = lines(dir + "/plan.txt");
  REQUIRE(planned.size() == 2);
  for (size_t i = 0; i < planned.size(); ++i) {
    INFO(planned[i]);
    CHECK(planned[i].rfind("cd '", 0) == 0);  // self-contained: runs from any working directory
    CHECK_THAT(planned[i], Catch::Contains(" --run-index " + std::to_string(i) + " --run-dir '"));
    CHECK_THAT(planned[i], !Catch::Contains("--plan"));
  }
  CHECK_FALSE(fs::exists(runs));  // the plan runs nothing

  // --report-only before anything ran: every run listed missing, nothing run.
  const auto empty = runCommand(bench + " --report-only");
  INFO(empty.output);
  REQUIRE(empty.exitCode == 0);
  CHECK_THAT(empty.output, Catch::Contains("2 of 2 runs missing"));
  CHECK_FALSE(fs::exists(runs + "default/run.log"));
  CHECK_FALSE(fs::exists(runs + "accurate/run.log"));
  CHECK_THAT(readText(dir + "/bench/report.md"), Catch::Contains("Incomplete: 2 of 2 runs"));

  // Line 2 of the plan, from another directory: exactly run 1.
  const auto second = runCommand("cd / && bash -c \"$(sed -n 2p " + dir + "/plan.txt)\"");
  INFO(second.output);
  REQUIRE(second.exitCode == 0);
  const std::string runZero = "default", runOne = "accurate";  // bench adds ACCURATE after the controllers
  CHECK(complete(runs + runOne));
  CHECK_FALSE(fs::exists(runs + runZero + "/summary.json"));
  const auto half = runCommand(bench + " --report-only");
  CHECK_THAT(half.output, Catch::Contains("1 of 2 runs missing"));
  CHECK_THAT(half.output, Catch::Contains("seq / " + runZero));

  // Where it ran.
  const auto machine = readJson(runs + runOne + "/summary.json").at("machine");
  CHECK(machine.at("host") == hostName());
  CHECK(machine.at("backend") == "cpu");
  CHECK(machine.at("threads_used") == 1);
  CHECK_FALSE(machine.at("cpu_model").get<std::string>().empty());

  // Wrong indices and shards are refused; the options exclude each other.
  const auto outOfRange = runCommand(bench + " --run-index 2");
  CHECK(outOfRange.exitCode == 1);
  CHECK_THAT(outOfRange.output, Catch::Contains("the matrix has 2 runs (0-1)"));
  for (const char* bad : {"2/2", "1", "a/2", "0/0"}) {
    const auto shard = runCommand(bench + " --shard " + bad);
    INFO(bad << ": " << shard.output);
    CHECK(shard.exitCode == 2);  // refused up front, as a usage error (issue 33)
    CHECK_THAT(shard.output, Catch::Contains("expected I/N"));
  }
  CHECK(runCommand(bench + " --plan " + dir + "/p2.txt --run-index 0").exitCode == 2);
  // A plan line whose index now means another run (the matrix changed since the plan) is refused.
  const auto moved = runCommand(bench + " --run-index 0 --run-dir " + runs + runOne);
  CHECK(moved.exitCode == 1);
  CHECK_THAT(moved.output, Catch::Contains("the matrix changed since the plan was written"));
  CHECK_FALSE(fs::exists(runs + runZero + "/run.log"));

  // --shard 0/1 runs the rest; the report is complete and says where the runs ran.
  const auto rest = runCommand(bench + " --shard 0/1");
  INFO(rest.output);
  REQUIRE(rest.exitCode == 0);
  CHECK(complete(runs + runZero));
  const auto report = runCommand(bench + " --report-only");
  INFO(report.output);
  REQUIRE(report.exitCode == 0);
  CHECK_THAT(report.output, !Catch::Contains("missing"));
  const std::string md = readText(dir + "/bench/report.md");
  CHECK_THAT(md, !Catch::Contains("Incomplete"));
  CHECK_THAT(md, Catch::Contains("> Machine: " + machine.at("cpu_model").get<std::string>() + ", 1 threads, cpu"));
  CHECK(lines(dir + "/bench/results.csv").size() == 3);

  // A run timed on another kind of machine: the report says so above its tables.
  auto other = readJson(runs + runZero + "/summary.json");
  other["machine"]["cpu_model"] = "Cortex-A15 (test)";
  other["machine"]["host"] = "board7";
  std::ofstream(runs + runZero + "/summary.json") << other.dump(2);
  REQUIRE(runCommand(bench + " --report-only").exitCode == 0);
  const std::string mixed = readText(dir + "/bench/report.md");
  CHECK_THAT(mixed, Catch::Contains("> Mixed machines: these runs were timed on 2 kinds of machine"));
  CHECK_THAT(mixed, Catch::Contains("Cortex-A15 (test)"));
  CHECK_THAT(readText(dir + "/bench/report.html"), Catch::Contains("Mixed machines"));
}

TEST_CASE("a claim from another host is respected while its heartbeat goes on and taken over once it stops",
          "[tools][system]") {
  const std::string dir = sb::test::scratchDir("cli_matrix_claim");
  const std::string bench = smallBench(dir);
  const std::string runDir = dir + "/bench/runs/seq/default";  // run 0
  // Run 0 is held by a worker on another host whose heartbeat is fresh.
  fs::create_directories(runDir);
  std::ofstream(runDir + "/.claim") << "node-elsewhere 4242\n";
  sb::test::CommandResult result;
  std::thread worker([&] { result = runCommand(bench + " --run-index 0"); });
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  CHECK_FALSE(fs::exists(runDir + "/run.log"));  // not run while the claim is alive
  // The heartbeat stops (the node is lost): past the lease, the claim is taken over and the run done here.
  fs::last_write_time(runDir + "/.claim", fs::file_time_type::clock::now() - std::chrono::seconds(120));
  worker.join();
  INFO(result.output);
  REQUIRE(result.exitCode == 0);
  CHECK_THAT(result.output, Catch::Contains("waiting for 1 runs that another process is running"));
  CHECK(complete(runDir));
  CHECK_FALSE(fs::exists(runDir + "/.claim"));
  for (const auto& entry : fs::directory_iterator(runDir))
    CHECK(entry.path().filename().string().rfind(".claim", 0) != 0);  // no stale claim left aside
}

TEST_CASE("dse and profile --report-only say what is missing and when machines were mixed",
          "[tools][system]") {
  const std::string dir = sb::test::scratchDir("cli_matrix_dse");
  REQUIRE(runCommand(kTool + " synth --out " + dir + "/seq --builtin-frames 4 --no-noise --width 160 --height 120 "
                             "--fx 131 --fy 131").exitCode == 0);
  std::ofstream(dir + "/small.json") << R"({"volume_resolution": 64})";
  const std::string dse = kTool + " dse " + dir + "/seq --out " + dir + "/dse --config " + dir +
                          "/small.json --csr 4,8 --icp 1e-5 --pd0 4 --max-ate 1.0 --no-prune --threads 1";
  REQUIRE(runCommand(dse + " --plan " + dir + "/plan.txt").exitCode == 0);
  REQUIRE(lines(dir + "/plan.txt").size() == 2);
  const auto one = runCommand(dse + " --run-index 0");
  INFO(one.output);
  REQUIRE(one.exitCode == 0);
  const auto partial = runCommand(dse + " --report-only");
  INFO(partial.output);
  REQUIRE(partial.exitCode == 0);
  CHECK_THAT(partial.output, Catch::Contains("1 of 2 runs missing"));
  CHECK_THAT(partial.output, Catch::Contains("incomplete: 1 of 2 settings have not finished"));
  auto best = readJson(dir + "/dse/best.json");
  CHECK(best.at("missing_runs").size() == 1);
  CHECK(lines(dir + "/dse/results.csv").size() == 2);  // header + the finished setting
  CHECK_FALSE(best.contains("mixed_machines"));

  // Both settings done, one of them timed elsewhere: the ranking says it mixes machines.
  REQUIRE(runCommand(dse + " --run-index 1").exitCode == 0);
  const std::string runs = dir + "/dse/runs";
  const fs::path first = fs::directory_iterator(runs)->path();
  auto summary = readJson((first / "summary.json").string());
  summary["machine"]["cpu_model"] = "Cortex-A15 (test)";
  std::ofstream(first / "summary.json") << summary.dump(2);
  const auto mixed = runCommand(dse + " --report-only");
  INFO(mixed.output);
  REQUIRE(mixed.exitCode == 0);
  CHECK_THAT(mixed.output, Catch::Contains("Mixed machines: these runs were timed on 2 kinds of machine"));
  best = readJson(dir + "/dse/best.json");
  CHECK_THAT(best.at("mixed_machines").get<std::string>(), Catch::Contains("the settings' ranking"));
  CHECK(best.at("machines").size() == 2);
  CHECK_FALSE(best.contains("missing_runs"));
  CHECK(lines(dir + "/dse/results.csv").size() == 3);

  // profile cannot build its table from part of the runs: it says which are missing and fails.
  const auto profile = runCommand(kTool + " profile " + dir + "/seq --out " + dir + "/profile --config " + dir +
                                  "/small.json --csr 8 --icp 1e-5 --pd0 4 --ir 1 --report-only");
  INFO(profile.output);
  CHECK(profile.exitCode == 1);
  CHECK_THAT(profile.output, Catch::Contains("2 of 2 runs missing"));
  CHECK_THAT(profile.output, Catch::Contains("the table needs every setting on every profiling sequence"));
  CHECK_FALSE(fs::exists(dir + "/profile/runs/seq"));  // nothing run

  // Its table, once every run is done, says when its speedups were timed on different machines (20 frames:
  // enough camera motion for a defined ATE).
  REQUIRE(runCommand(kTool + " synth --out " + dir + "/seq20 --builtin-frames 20 --no-noise --width 160 --height "
                             "120 --fx 131 --fy 131").exitCode == 0);
  const std::string profileCmd = kTool + " profile " + dir + "/seq20 --out " + dir + "/profile20 --config " + dir +
                                 "/small.json --csr 8 --icp 1e-5 --pd0 4 --ir 1 --threads 1";
  const auto full = runCommand(profileCmd);
  INFO(full.output);
  REQUIRE(full.exitCode == 0);
  CHECK_FALSE(readJson(dir + "/profile20/tc_table.json").contains("mixed_machines"));
  const fs::path profiled = fs::directory_iterator(dir + "/profile20/runs/seq20")->path() / "summary.json";
  auto timed = readJson(profiled.string());
  timed["machine"]["backend"] = "opencl";
  timed["machine"]["device"] = "Mali-T628 (test)";
  std::ofstream(profiled) << timed.dump(2);
  const auto table = runCommand(profileCmd + " --report-only");
  INFO(table.output);
  REQUIRE(table.exitCode == 0);
  CHECK_THAT(table.output, Catch::Contains("Mixed machines"));
  const auto tc = readJson(dir + "/profile20/tc_table.json");
  CHECK_THAT(tc.at("mixed_machines").get<std::string>(), Catch::Contains("the speedups and the Pareto front"));
  CHECK_THAT(tc.at("mixed_machines").get<std::string>(), Catch::Contains("opencl Mali-T628 (test)"));
}

TEST_CASE("a worker's claim is kept alive by its heartbeat while its run goes on", "[tools][system]") {
  const std::string dir = sb::test::scratchDir("cli_matrix_heartbeat");
  // A run of about 4 s (on an idle 2-core machine): long enough for a heartbeat (every 2 s).
  REQUIRE(runCommand(kTool + " synth --out " + dir + "/seq --builtin-frames 400 --no-noise --width 160 --height 120 "
                             "--fx 131 --fy 131").exitCode == 0);
  std::ofstream(dir + "/small.json") << R"({"volume_resolution": 64})";
  const std::string bench = kTool + " bench " + dir + "/seq --out " + dir + "/bench --config " + dir +
                            "/small.json --controllers default --threads 1";
  const std::string claim = dir + "/bench/runs/seq/default/.claim";
  sb::test::CommandResult result;
  std::thread worker([&] { result = runCommand(bench + " --run-index 0"); });
  bool refreshed = false;
  std::optional<fs::file_time_type> seen;
  for (int i = 0; i < 300 && !refreshed; ++i) {  // 30 s at most
    std::error_code ec;
    const auto t = fs::last_write_time(claim, ec);
    if (!ec && !seen) seen = t;
    if (!ec && seen && t > *seen) refreshed = true;
    if (ec && seen) break;  // released: the run ended before a heartbeat
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  worker.join();
  INFO(result.output);
  REQUIRE(result.exitCode == 0);
  REQUIRE(seen);
  CHECK(refreshed);
  CHECK_FALSE(fs::exists(claim));
}
