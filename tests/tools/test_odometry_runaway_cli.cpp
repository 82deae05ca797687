// A view that runs away while the wheels say otherwise is not `good` (issue 41 item 5, with odometry), as a user
// runs it: the corridor drive's first 60 frames at 160x120 with their odometry (the robot setting off from rest),
// tracked at a coarse fixed compute size (`--controller fixed --knobs csr=2`: 80x60), where ICP matches the model
// 0.07-0.22 m ahead in one frame while the robot creeps at a few millimetres. Measured before the inertia rule
// (odometry/odometry_fusion.h viewBreaksInertia): the wheels were rejected as a "slip" and the view stood, 22
// good or weak frames moving 3 cm or more unlike the truth, ATE 79.5 cm. With it: the view is discarded there
// and the pose follows the odometry (state odometry), no good or weak frame off by 3 cm, ATE 2.4 cm.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/files.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"
#include "tests/support/tum_positions.h"

using sb::test::readJson;
using sb::test::runCommand;

namespace {

const std::string kTool = sb::test::testBinary("SB_TEST_SLAMBOOSTER", SB_SLAMBOOSTER_BIN);

struct Judged {
  int posed = 0, offGood = 0, followed = 0;
};

// A run's frames against the truth: good or weak frames whose motion is 3 cm or more unlike the truth's.
Judged judge(const std::string& run, const std::vector<std::vector<double>>& truth) {
  Judged j;
  std::ifstream frames(run + "/frames.jsonl");
  for (std::string line; std::getline(frames, line);) {
    const auto f = nlohmann::json::parse(line);
    const size_t i = f.at("frame").get<size_t>();
    const std::string state = f.at("state").get<std::string>();
    j.posed += state != "lost";
    j.followed += state == "odometry";
    if (i == 0 || i >= truth.size() || (state != "good" && state != "weak")) continue;
    double trueStep = 0;
    for (int k = 0; k < 3; ++k) trueStep += std::pow(truth[i][k] - truth[i - 1][k], 2);
    const double off = std::abs(f.at("velocity_m_per_frame").get<double>() - std::sqrt(trueStep));
    if (off > 0.03) {
      UNSCOPED_INFO("frame " << i << " " << state << ": moved " << f.at("velocity_m_per_frame").get<double>()
                             << " m, the truth " << std::sqrt(trueStep) << " m");
      ++j.offGood;
    }
  }
  return j;
}

// The drive's first 60 frames at 160x120 into dir/drive, run at the coarse fixed size with tracking rate `tr`:
// the run judged against the truth, its ATE in `ate`.
Judged coarseRun(const std::string& dir, int tr, double& ate) {
  const auto synth = runCommand(kTool + " synth --out " + dir +
                                "/drive --scene corridor --stress drive --seed 0 --frames 60 --width 160 --height 120"
                                " --fx 120 --fy 120 --threads 1 --overwrite");
  INFO(synth.output);
  REQUIRE(synth.exitCode == 0);
  const auto run = runCommand(kTool + " run " + dir + "/drive --out " + dir +
                              "/run --controller fixed --knobs csr=2,icp=1e-5,pd=10:5:4,tr=" + std::to_string(tr) +
                              ",ir=2 --threads 1 --volume-size 5 --quiet");
  INFO(run.output);
  REQUIRE(run.exitCode == 0);
  const auto truth = sb::test::tumPositions(dir + "/drive/groundtruth.txt");
  REQUIRE(truth.size() == 60);
  ate = readJson(dir + "/run/summary.json").at("ate").at("rmse_m").get<double>();
  return judge(dir + "/run", truth);
}

}  // namespace

TEST_CASE("with odometry, a coarse view that runs away from the wheels is not good", "[odometry][system]") {
  double ate = 0.0;
  const Judged j = coarseRun(sb::test::scratchDir("test_odometry_runaway_cli"), 1, ate);
  CHECK(j.offGood == 0);
  CHECK(j.posed == 60);
  CHECK(j.followed > 0);  // the runaway happens at this size: the test would not show the rule otherwise
  CHECK(ate < 0.10);
}

// Right after frames that followed the wheels, the platform's velocity is theirs. First the rule at tr 3 (two frames
// in three take the wheels' pose): on the drive above every tracked frame comes after wheel-posed ones and the coarse
// view jumps ahead of the model; it is discarded there, not good (this case passed before the fix too). Then the
// held-out drive where the fault was found (seed 2, its base -2% scale, +4% turn scale, -0.2 deg/s; its first 76
// frames), `adaptive` at full resolution: before, a frame on the odometry left no velocity to judge the next by, and
// the view's 0.117 m jump at frame 56 (the truth 0.042) stood, `good` (a001997: one good frame off the truth, ATE 3.79
// cm; this case fails there). Since the wheels' prediction carries the noise of the whole interval since the view
// last fixed the pose, the fusion takes the runs ahead (0.05-0.09 m a frame in frames 45-57) along the corridor as
// the wheels say before the inertia rule is needed: the view still runs ahead, and no frame it leaves off is good.
TEST_CASE("after frames on the wheels, a view that jumps ahead of them is not good", "[odometry][system]") {
  double ate = 0.0;
  const Judged j = coarseRun(sb::test::scratchDir("test_odometry_runaway_cli_skipped"), 3, ate);
  CHECK(j.offGood == 0);
  CHECK(j.posed == 60);
  CHECK(j.followed > 0);  // the runaway happens after skipped frames here: the test would not show the rule otherwise
  CHECK(ate < 0.10);
}

TEST_CASE("on the held-out drive where it was found, adaptive's view runs ahead and no such frame is good",
          "[odometry][system]") {
  const std::string dir = sb::test::scratchDir("test_odometry_runaway_cli_inertia");
  const auto synth = runCommand(kTool + " synth --out " + dir +
                                "/drive --scene corridor --stress drive --seed 2 --width 320 --height 240 --fx 240.6"
                                " --fy 240 --odom-scale -0.02 --odom-yaw-scale 0.04 --odom-yaw-bias -0.2 --overwrite");
  INFO(synth.output);
  REQUIRE(synth.exitCode == 0);
  {  // the drive's first 76 frames (a shorter synth plans a different drive)
    std::ifstream in(dir + "/drive/depth.txt");
    std::ostringstream head;
    int rows = 0;
    for (std::string line; std::getline(in, line) && rows < 76;) {
      head << line << '\n';
      rows += !line.empty() && line[0] != '#';
    }
    in.close();
    std::ofstream(dir + "/drive/depth.txt") << head.str();
  }
  const auto run = runCommand(kTool + " run " + dir + "/drive --out " + dir +
                              "/run --controller adaptive --threads 1 --volume-size 5 --quiet");
  INFO(run.output);
  REQUIRE(run.exitCode == 0);
  const auto truth = sb::test::tumPositions(dir + "/drive/groundtruth.txt");
  const Judged j = judge(dir + "/run", truth);
  CHECK(j.offGood == 0);
  CHECK(j.posed == 76);
  int ranAhead = 0;  // tracked frames whose own track moved 3 cm or more beyond the truth
  std::ifstream frames(dir + "/run/frames.jsonl");
  for (std::string line; std::getline(frames, line);) {
    const auto f = nlohmann::json::parse(line);
    const size_t i = f.at("frame").get<size_t>();
    if (i == 0 || !f.at("tracked").get<bool>()) continue;
    double trueStep = 0;
    for (int k = 0; k < 3; ++k) trueStep += std::pow(truth[i][k] - truth[i - 1][k], 2);
    ranAhead += f.at("tracked_velocity_m_per_frame").get<double>() > std::sqrt(trueStep) + 0.03;
  }
  CHECK(ranAhead > 0);  // the view runs ahead here: the test would not show anything otherwise
  CHECK(readJson(dir + "/run/summary.json").at("ate").at("rmse_m").get<double>() < 0.02);
}
