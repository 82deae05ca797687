// Issue 53's findings at slamboosterd's doors (the fourth round of attacks, on 1121ad2), each checked as a
// client or an operator meets it; run against another build with SB_TEST_SLAMBOOSTERD and
// SB_TEST_SLAMBOOSTERCTL (tests/support/test_data.h):
// - one ?ODOM sample stamped 9.9e9 s stood as the newest and every later sample was refused: 0 frames had
//   odometry for the rest of the run;
// - --check-config said "valid" for what start-up refuses (source.odometry missing, a FIFO or a directory, a
//   garbage source.camera_mount, a push source.path that is a regular file);
// - `slamboosterctl odom FILE` with 10,000 samples said all were accepted while the daemon keeps 4,096.

#include <signal.h>
#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <fstream>
#include <iomanip>
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

constexpr int kDriveFrames = 40;

// A short drive (160x120) with its odometry.txt, rendered once.
struct Drive {
  std::string sequence, pipelineConfig;
  Drive() {
    const std::string dir = sb::test::scratchDir(std::string(SB_E2E_SCRATCH) + "_drive");  // not fixture()'s
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

std::vector<std::string> socketDaemon(const std::string& socket, const std::string& out) {
  // Recorded pacing at a fifth of the speed: the pushes land before the frames that need them.
  return {kDaemon, "--input", drive().sequence, "--out", out, "--socket", socket, "--pacing", "recorded",
          "--at-end", "exit", "--controller", "fixed", "--set", "slam.threads=1", "--set",
          "slam.pipeline_config=" + drive().pipelineConfig, "--set", "source.odometry=socket", "--set",
          "source.speed=0.2"};
}

// The drive's first odometry line with its stamp replaced by `stamp`.
std::string oneSample(const std::string& path, const std::string& stamp) {
  std::ifstream in(drive().sequence + "/odometry.txt");
  std::string line;
  while (std::getline(in, line) && (line.empty() || line[0] == '#')) {
  }
  std::ofstream(path) << stamp << line.substr(line.find(' ')) << "\n";
  return path;
}

}  // namespace

TEST_CASE("one absurd ?ODOM stamp is refused alone: the robot's samples after it are taken", "[daemon][system][odometry][issue53]") {
  TempDir tmp;
  const std::string socket = tmp.path + "/s.sock";
  ChildProcess d(socketDaemon(socket, tmp.path + "/d"), {}, tmp.path + "/log.txt");
  REQUIRE(sb::test::waitForPath(socket, 20));
  // 9.9e9 s lies inside the range every door accepts ([0, 1e10]), far past the robot's clock. Refused when a
  // frame has set the clock; before the first frame, the robot's next samples undo it (odometry_track.h).
  const auto absurd = runCommand(kCtl + " --socket " + socket + " odom " + oneSample(tmp.path + "/absurd.txt", "9900000000"));
  INFO(absurd.output);
  const auto push = runCommand(kCtl + " --socket " + socket + " odom " + drive().sequence + "/odometry.txt");
  INFO(push.output);
  CHECK(push.exitCode == 0);
  REQUIRE(d.wait(120) == 0);
  INFO(d.log());
  const sb::RunSummary s = sb::readRunSummary(tmp.path + "/d/summary.json");
  REQUIRE(s.odometry);
  CHECK(s.odometry->framesWithPose == kDriveFrames - 1);  // was 0: every sample after the absurd one refused
}

TEST_CASE("--check-config and start-up agree on the source's files and mount", "[daemon][system][config][issue53]") {
  TempDir tmp;
  const std::string fifo = tmp.path + "/fifo.txt";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  const std::string regular = tmp.path + "/regular";
  std::ofstream(regular) << "a regular file\n";
  const std::string badLine = tmp.path + "/bad-odometry.txt";
  std::ofstream(badLine) << "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0\n";
  struct Case {
    std::string name, key;
    std::vector<std::string> args;
    std::string input = fixture().sequence;
  };
  const std::vector<Case> cases = {
      {"odometry missing", "source.odometry", {"--set", "source.odometry=" + tmp.path + "/none.txt"}},
      {"odometry a FIFO", "source.odometry", {"--set", "source.odometry=" + fifo}},
      {"odometry a directory", "source.odometry", {"--set", "source.odometry=" + tmp.path}},
      {"odometry with a bad line", "bad-odometry.txt:2", {"--set", "source.odometry=" + badLine}},
      {"camera_mount garbage", "source.camera_mount", {"--set", "source.camera_mount=garbage"}},
      {"camera_mount far away", "source.camera_mount", {"--set", "source.camera_mount=1e300 0 0 0 0 0 1"}},
      {"camera_mount zero quaternion", "source.camera_mount", {"--set", "source.camera_mount=0 0 0.5 0 0 0 0"}},
      {"push path a regular file", "source.path", {"--set", "source.type=push"}, regular},
  };
  for (const Case& c : cases) {
    INFO(c.name);
    std::string args;
    for (const auto& a : c.args) args += " '" + a + "'";
    const std::string common = " --input " + c.input + " --socket " + tmp.path + "/s.sock --out " +
                               tmp.path + "/out --set slam.pipeline_config=" + fixture().pipelineConfig + args;
    const auto check = runCommand("timeout 20 " + kDaemon + " --check-config" + common + " 2>&1");
    INFO("check: " << check.output);
    CHECK(check.exitCode == 2);
    CHECK(check.output.find(c.key) != std::string::npos);
    const auto start = runCommand("timeout 20 " + kDaemon + common + " --at-end exit 2>&1");
    INFO("start: " << start.output);
    CHECK(start.exitCode == 2);
    CHECK(start.output.find(c.key) != std::string::npos);
  }
  // And a valid odometry file and mount pass both.
  const auto good = runCommand(kDaemon + " --check-config --input " + fixture().sequence + " --set source.odometry=" +
                               drive().sequence + "/odometry.txt --set 'source.camera_mount=0 0 0.5 0 0 0 1'");
  INFO(good.output);
  CHECK(good.exitCode == 0);
}

TEST_CASE("slamboosterctl odom says what the daemon kept of a long file", "[daemon][system][odometry][issue53]") {
  TempDir tmp;
  const std::string socket = tmp.path + "/s.sock";
  auto args = socketDaemon(socket, tmp.path + "/d");
  args.insert(args.end(), {"--set", "source.speed=0.05"});  // the frames wait while 10,000 samples go in
  ChildProcess d(args, {}, tmp.path + "/log.txt");
  REQUIRE(sb::test::waitForPath(socket, 20));
  const std::string file = tmp.path + "/long.txt";
  {
    std::ofstream out(file);
    out << std::fixed << std::setprecision(6);
    for (int i = 0; i < 10000; ++i) out << 1000.0 + 0.01 * i << " " << 0.001 * i << " 0 0 0 0 0 1\n";
  }
  const auto push = runCommand(kCtl + " --socket " + socket + " odom " + file);
  INFO(push.output);
  // It said "10000 samples of ... accepted" (rc 0) while 5,904 of them were already gone.
  CHECK(push.exitCode == 1);
  CHECK(push.output.find("4096") != std::string::npos);
  CHECK(push.output.find("5904 oldest samples") != std::string::npos);
  d.signal(SIGTERM);
  d.wait(60);
}
