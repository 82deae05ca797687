// The robot's odometry through its doors (issue 41): one synthetic drive with odometry.txt, run by
// `slambooster run` (the file beside depth.txt), by the daemon's replay (the same file, source.odometry auto)
// and by the daemon fed over its socket (source.odometry socket, `slamboosterctl odom FILE` pushing ?ODOM).
// Each run is given the same samples (the summary's odometry counts, and the odometry camera's path over the
// frames, which interpolates them at every frame) and, fused, gives the same trajectory.

#include <signal.h>

#include <catch2/catch.hpp>
#include <fstream>
#include <iterator>
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

constexpr int kDriveFrames = 60;

// A short drive (160x120) with its odometry, rendered once.
struct Drive {
  std::string sequence, pipelineConfig;
  Drive() {
    const std::string dir = sb::test::scratchDir(SB_E2E_SCRATCH);
    sequence = dir + "/drive";
    const auto synth = runCommand(kTool + " synth --scene corridor --stress drive --seed 1 --frames " +
                                  std::to_string(kDriveFrames) + " --width 160 --height 120 --fx 120 --fy 120 " +
                                  "--threads 1 --overwrite --out " + sequence);
    if (synth.exitCode != 0) throw std::runtime_error("synth failed: " + synth.output);
    pipelineConfig = dir + "/pipeline.json";
    std::ofstream(pipelineConfig) << R"({"volume_resolution": 64})";
  }
};

const Drive& drive() {
  static const Drive d;
  return d;
}

std::vector<std::string> driveDaemonArgs(const std::string& socket, const std::string& out, const std::string& odometry,
                                    const std::string& pacing) {
  return {kDaemon, "--input", drive().sequence, "--out", out, "--socket", socket, "--pacing", pacing,
          "--at-end", "exit", "--controller", "fixed", "--set", "slam.threads=1", "--set",
          "slam.pipeline_config=" + drive().pipelineConfig, "--set", "source.odometry=" + odometry};
}

std::string poses(const std::string& trajectory) {  // the data lines, without the comment that names the front end
  std::ifstream in(trajectory);
  std::string out;
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] != '#') out += line + "\n";
  return out;
}

}  // namespace

TEST_CASE("odometry: run, the daemon's replay and the socket give the run the same samples", "[daemon][system][odometry]") {
  TempDir tmp;
  const std::string runOut = tmp.path + "/run";
  const auto run = runCommand(kTool + " run " + drive().sequence + " --out " + runOut + " --config " +
                              drive().pipelineConfig + " --controller fixed --threads 1 --quiet");
  INFO(run.output);
  REQUIRE(run.exitCode == 0);
  const sb::RunSummary fromRun = sb::readRunSummary(runOut + "/summary.json");
  REQUIRE(fromRun.odometry);
  CHECK(fromRun.odometry->source == drive().sequence + "/odometry.txt");
  const size_t samples = dataLines(drive().sequence + "/odometry.txt");
  CHECK(fromRun.odometry->samples == samples);
  CHECK(fromRun.odometry->framesWithPose == kDriveFrames - 1);  // the first frame precedes the first sample
  CHECK(fromRun.odometry->pathM > 1.0);

  SECTION("--no-odometry: none") {
    const auto bare = runCommand(kTool + " run " + drive().sequence + " --out " + tmp.path + "/bare --config " +
                                 drive().pipelineConfig + " --controller fixed --threads 1 --quiet --no-odometry");
    REQUIRE(bare.exitCode == 0);
    CHECK_FALSE(sb::readRunSummary(tmp.path + "/bare/summary.json").odometry);
  }
  // The same samples reach the runner (count, coverage and the path interpolated at every frame, exactly)
  // and, fused, the same trajectory.
  const auto sameAsRun = [&](const std::string& out, const std::string& source) {
    const sb::RunSummary s = sb::readRunSummary(out + "/summary.json");
    REQUIRE(s.odometry);
    CHECK(s.odometry->source == source);
    CHECK(s.odometry->samples == fromRun.odometry->samples);
    CHECK(s.odometry->framesWithPose == fromRun.odometry->framesWithPose);
    CHECK(s.odometry->pathM == fromRun.odometry->pathM);
    CHECK(poses(out + "/trajectory.tum") == poses(runOut + "/trajectory.tum"));
  };
  SECTION("the daemon's replay reads odometry.txt") {
    ChildProcess d(driveDaemonArgs(tmp.path + "/s.sock", tmp.path + "/d", "auto", "fast"), {}, tmp.path + "/log.txt");
    REQUIRE(d.wait(60) == 0);
    INFO(d.log());
    sameAsRun(tmp.path + "/d", drive().sequence + "/odometry.txt");
  }
  SECTION("the socket: slamboosterctl odom pushes the file with ?ODOM") {
    // Recorded pacing at a fifth of the speed: the samples are all in before the second frame (0.17 s).
    auto args = driveDaemonArgs(tmp.path + "/s.sock", tmp.path + "/d", "socket", "recorded");
    args.insert(args.end(), {"--set", "source.speed=0.2"});
    ChildProcess d(args, {}, tmp.path + "/log.txt");
    REQUIRE(sb::test::waitForPath(tmp.path + "/s.sock", 20));
    const auto push = runCommand(kCtl + " --socket " + tmp.path + "/s.sock odom " + drive().sequence + "/odometry.txt");
    INFO(push.output);
    CHECK(push.exitCode == 0);
    CHECK(push.output.find(std::to_string(samples) + " samples") != std::string::npos);
    // Pushed again: refused, naming the stamp that does not increase.
    const auto again = runCommand(kCtl + " --socket " + tmp.path + "/s.sock odom " + drive().sequence + "/odometry.txt");
    CHECK(again.exitCode == 1);
    CHECK(again.output.find("stamps must increase") != std::string::npos);
    REQUIRE(d.wait(120) == 0);
    INFO(d.log());
    sameAsRun(tmp.path + "/d", "socket");
  }
  // The navigation map with "up": "none": the robot's odometry says which way is up, as in `slambooster run`
  // (the daemon dropped the map at the pass's start before: no grid on a robot unless the mount was given).
  SECTION("output.navmap up none: the grid's frame from the odometry, none without it") {
    const std::string settings = tmp.path + "/navmap.json";
    std::ofstream(settings) << R"({"up": "none"})";
    for (const std::string odometry : {"auto", "none"}) {
      INFO("source.odometry " << odometry);
      const std::string out = tmp.path + "/map-" + odometry;
      auto args = driveDaemonArgs(tmp.path + "/s.sock", out, odometry, "fast");
      args.insert(args.end(), {"--set", "output.navmap=" + settings});
      ChildProcess d(args, {}, tmp.path + "/log-" + odometry + ".txt");
      REQUIRE(d.wait(60) == 0);
      INFO(d.log());
      const bool grid = std::ifstream(out + "/map.pgm").good();
      CHECK(grid == (odometry == "auto"));
      if (!grid) continue;
      std::ifstream frame(out + "/map_frame.json");
      const std::string text((std::istreambuf_iterator<char>(frame)), std::istreambuf_iterator<char>());
      CHECK(text.find("odometry") != std::string::npos);
    }
  }
  SECTION("source.odometry none: ?ODOM refused") {
    auto args = driveDaemonArgs(tmp.path + "/s.sock", tmp.path + "/d", "none", "recorded");
    ChildProcess d(args, {}, tmp.path + "/log.txt");
    REQUIRE(sb::test::waitForPath(tmp.path + "/s.sock", 20));
    const auto push = runCommand(kCtl + " --socket " + tmp.path + "/s.sock odom " + drive().sequence + "/odometry.txt");
    CHECK(push.exitCode == 1);
    CHECK(push.output.find("source.odometry is \"none\"") != std::string::npos);
    d.signal(SIGTERM);
    REQUIRE(d.wait(60) == 0);
    CHECK_FALSE(sb::readRunSummary(tmp.path + "/d/summary.json").odometry);
  }
}
