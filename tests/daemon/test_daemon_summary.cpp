// One summary.json for both front ends (issue 32): a daemon pass and `slambooster run` of the same frames,
// config and controller write summaries that are equal but for the fields that must differ (the front end,
// the daemon's pass, and the times).

#include <signal.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "report/run_summary.h"
#include "tests/daemon/daemon_e2e.h"
#include "tests/daemon/process.h"
#include "tests/support/run_command.h"

using namespace sb::test::e2e;
using sb::test::ChildProcess;
using sb::test::runCommand;

namespace {

// The summary without what depends on the front end or on the clock.
nlohmann::json comparable(const sb::RunSummary& s) {
  nlohmann::json j = s.toJson();
  for (const char* key : {"front_end", "daemon", "computation_ms_per_frame", "controller_ms_per_frame",
                          "stage_ms_per_frame", "cpu_ms_per_frame"})
    j.erase(key);
  // The daemon listens for odometry on its socket (source.odometry auto, no odometry.txt): nothing came.
  if (j.contains("odometry") && j["odometry"].value("source", "") == "socket" && j["odometry"].value("samples", 1) == 0)
    j.erase("odometry");
  return j;
}

}  // namespace

TEST_CASE("slamboosterd and slambooster run write the same summary of the same frames", "[daemon][system]") {
  TempDir tmp;
  const std::string socket = tmp.path + "/s.sock", daemonOut = tmp.path + "/daemon",
                    runOut = tmp.path + "/run";
  for (const std::string controller : {"fixed", "adaptive"}) {
    INFO("controller " << controller);
    auto args = daemonArgs(socket, daemonOut + controller, "fast", "exit");
    args.back() = controller;                                                                // --controller
    args.insert(args.end(), {"--set", "slam.threads=1", "--set", "output.model_png=true"});  // as `run` does
    ChildProcess d(args, {}, tmp.path + "/log-" + controller + ".txt");
    INFO(d.log());
    REQUIRE(d.wait(60) == 0);
    const auto run =
        runCommand(kTool + " run " + fixture().sequence + " --out " + runOut + controller + " --config " +
                   fixture().pipelineConfig + " --controller " + controller + " --threads 1 --quiet");
    INFO(run.output);
    REQUIRE(run.exitCode == 0);

    const sb::RunSummary fromDaemon = sb::readRunSummary(daemonOut + controller + "/summary.json");
    const sb::RunSummary fromRun = sb::readRunSummary(runOut + controller + "/summary.json");
    CHECK(fromDaemon.frontEnd == "daemon");
    CHECK(fromRun.frontEnd == "run");
    REQUIRE(fromDaemon.daemon);
    CHECK(fromDaemon.daemon->pass == 1);
    CHECK_FALSE(fromRun.daemon);
    CHECK(fromDaemon.controller == controller);
    CHECK(fromDaemon.frames == static_cast<size_t>(kFrames));
    CHECK(comparable(fromDaemon).dump(2) == comparable(fromRun).dump(2));
  }
}

TEST_CASE("slamboosterd: a controller switched by ?CONTROL stays in force for the next passes of a loop",
          "[daemon][system]") {
  // Before (issue 32) a new pass started with the configured controller again after a ?CONTROL switch, while
  // a SIGHUP switch stayed: the pass took its name from the settings copy that ?CONTROL did not rename.
  TempDir tmp;
  const std::string socket = tmp.path + "/s.sock", out = tmp.path + "/out";
  auto args = daemonArgs(socket, out, "fast", "loop");
  args.insert(args.end(), {"--set", "source.max_frames=5", "--set", "output.report=false"});
  ChildProcess d(args, {}, tmp.path + "/log.txt");
  REQUIRE(sb::test::waitForPath(socket, 20));
  INFO(d.log());
  REQUIRE(sb::test::waitForPath(passDirectory(out, 2) + "/summary.json", 60));  // looping
  CHECK(ctlJson(socket, "control --controller accurate")["controller"] == "accurate");
  // The pass after the next: the next one's directory may appear after this listing while its controller was
  // taken before the switch.
  const int next = passDirectories(out).back() + 2;
  const std::string summary = passDirectory(out, next) + "/summary.json";
  REQUIRE(sb::test::waitForPath(summary, 60));
  CHECK(sb::readRunSummary(summary).controller == "accurate");
  const nlohmann::json status = ctlJson(socket, "status");
  CHECK(status["controller"] == "accurate");
  CHECK_FALSE(status.contains("kept_map"));  // no map store: as POSE, STATUS says nothing of one
  d.signal(SIGTERM);
  CHECK(d.wait(30) == 0);
}

TEST_CASE("slamboosterd: STATUS says kept_map in a pass started with a kept map", "[daemon][system]") {
  // Protocol 1.11: before, POSE, frames.jsonl and the ROS diagnostics said it and STATUS did not. A looping
  // replay with output.map_store: pass 1 makes the store, every later pass starts in it.
  TempDir tmp;
  const std::string socket = tmp.path + "/s.sock", out = tmp.path + "/out", store = tmp.path + "/store";
  auto args = daemonArgs(socket, out, "fast", "loop");
  args.insert(args.end(), {"--set", "output.report=false", "--set", "output.map_store=" + store});
  ChildProcess d(args, {}, tmp.path + "/log.txt");
  REQUIRE(sb::test::waitForPath(socket, 20));
  INFO(d.log());
  // Pass 2 started in the kept map and ended: its frames said kept_map; the pass after it does too.
  REQUIRE(sb::test::waitForPath(passDirectory(out, 3), 90));
  const nlohmann::json status = ctlJson(socket, "status");
  INFO(status.dump());
  REQUIRE(status.contains("kept_map"));
  CHECK((status["kept_map"] == "localising" || status["kept_map"] == "localised"));
  d.signal(SIGTERM);
  CHECK(d.wait(30) == 0);
  // Pass 1 made the store: none of its frames was in a kept map; pass 2's were.
  for (int pass : {1, 2}) {
    std::ifstream log(passDirectory(out, pass) + "/frames.jsonl");
    REQUIRE(log);
    std::string line, last;
    size_t said = 0, frames = 0;
    while (std::getline(log, line)) {
      const nlohmann::json j = nlohmann::json::parse(line);
      if (!j.contains("frame")) continue;
      ++frames;
      said += j.contains("kept_map");
    }
    INFO("pass " << pass);
    CHECK(frames > 0);
    CHECK(said == (pass == 1 ? 0 : frames));
  }
}
