// The fault watch at `slambooster run` (issue 52; docs/wheel-faults.md), as a user runs it: a corridor
// drive's first 10 s at 320x240 with a stall (the robot stands 2 s at a place whose view fixes the corridor's axis
// while its wheels read 1 m/s on), the watch on ({"odometry": {"dispute_s": 0.3}}). At 160x120 the same drive's
// view does not fix the axis where it stands (ICP left the wheels' prediction in place along it): no view can
// tell a stall there, and this test would show nothing. Before, the view's sudden stop broke the body's inertia frame after frame:
// the view was discarded, the pose followed the wheels and the map grew at their poses (the same run with the
// watch off ends the stall metres ahead of the truth, `good`). A view that stands where it last fixed the pose while
// the wheels drive on is a stall's signature: it holds, the wheels are `slipping` and not used until they agree.
// Second: a camera mount measured 2 degrees off, through the U-turn and back (mount_sigma_deg). Third: wheels gone
// wrong for 6 s while the view could take over (reversed steps under `adaptive`, a 20 deg/s gyro bias under DEFAULT).
// Fourth: wheels reading twice the distance, withheld through the U-turn, where the end wall leaves the height free.
// Fifth: wheels reading zero while the robot drives on, where the view barely fixes the corridor's axis.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <tuple>
#include <vector>

#include "core/trajectory.h"
#include "tests/support/anchored_frames.h"
#include "tests/support/files.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

using sb::test::runCommand;

namespace {

const std::string kTool = sb::test::testBinary("SB_TEST_SLAMBOOSTER", SB_SLAMBOOSTER_BIN);
constexpr int kFrames = 300;
constexpr double kStallAtS = 7.2, kStallS = 2.0;
constexpr size_t kMountFrames = 1228;  // the whole drive: the U-turn at frames 550-700, the way back to 41 s

struct Verdict {
  int goodOff = 0;        // `good` frames more than offM from the truth (both anchored at the first frame)
  int slipping = 0;       // frames whose wheels were found slipping
  int unposed = 0;        // frames `lost` (the pose held, not the camera's)
  double worstGoodM = 0;  // the worst error of a `good` frame
};

// The run's poses against the truth, anchored at the first frame's whole pose (as a robot's map frame is: no
// alignment fitted; tests/support/anchored_frames.h says why not by its position alone).
Verdict judge(const std::string& run, const sb::Trajectory& truth, double offM = 0.3) {
  Verdict v;
  for (const sb::test::AnchoredFrame& f : sb::test::anchoredFrames(run, truth)) {
    if (f.state == "good") {
      v.goodOff += f.errorM > offM;
      v.worstGoodM = std::max(v.worstGoodM, f.errorM);
    }
    v.unposed += f.state == "lost";
    const auto& o = f.line.at("odometry");
    v.slipping += o.contains("fault") && o.at("fault").get<std::string>() == "slipping";
  }
  return v;
}

}  // namespace

TEST_CASE("a stall with spinning wheels: the view holds, the wheels are slipping, no good pose strays",
          "[odometry][system]") {
  const std::string dir = sb::test::scratchDir("test_wheel_faults_cli");
  char stall[64];
  std::snprintf(stall, sizeof stall, " --odom-stall %.1f,%.1f,1.0", kStallAtS, kStallS);
  const auto synth = runCommand(kTool + " synth --out " + dir + "/drive --scene corridor --stress drive --seed 23 --frames " +
                                std::to_string(kFrames) + " --width 320 --height 240 --fx 240.6 --fy 240 --threads 1 --overwrite" +
                                stall);
  INFO(synth.output);
  REQUIRE(synth.exitCode == 0);
  const sb::Trajectory truth = sb::readTumTrajectory(dir + "/drive/groundtruth.txt");
  REQUIRE(truth.size() == kFrames);
  std::ofstream(dir + "/watch.json") << R"({"odometry": {"dispute_s": 0.3}})";
  std::ofstream(dir + "/unwatched.json") << R"({"odometry": {"dispute_s": 0}})";
  const std::string knobs = " --controller default --threads 1 --volume-size 5 --quiet";

  const auto off = runCommand(kTool + " run " + dir + "/drive --out " + dir + "/off --config " + dir + "/unwatched.json" +
                              knobs);
  INFO(off.output);
  REQUIRE(off.exitCode == 0);
  const Verdict without = judge(dir + "/off", truth);
  // The fault is one the inertia rule does not survive (otherwise this test would show nothing).
  CHECK(without.goodOff > 0);

  const auto on = runCommand(kTool + " run " + dir + "/drive --out " + dir + "/on --config " + dir + "/watch.json" + knobs);
  INFO(on.output);
  REQUIRE(on.exitCode == 0);
  const Verdict with = judge(dir + "/on", truth);
  INFO("worst good frame " << with.worstGoodM << " m (off: " << without.worstGoodM << " m)");
  CHECK(with.goodOff == 0);
  CHECK(with.slipping > 0);
}

TEST_CASE("a camera mount measured 2 degrees off: the way back after a U-turn is not levelled to the wrong tilt",
          "[odometry][system]") {
  // The odometry's tilt is absolute only up to the mount it assumes: after a U-turn a mount off by e tilts the
  // odometry's camera by 2e. Held to it (mount_sigma_deg 0: the mount taken as exact and not learnt, as before
  // 2026-12-07) the map leaned and the way back climbed: `good` frames more than 0.5 m off. With the mount's sigma,
  // a frame is levelled only by an anchor at its own heading (odometry/motion_model.h TiltAnchor), and the mount's
  // tilt is learnt from the floor the view shows on the first straight (odometry/floor_up.h): the true tilt error
  // here is 1.80 degrees (-1.5 about the optical axis, -1 about x).
  const std::string dir = sb::test::scratchDir("test_wheel_faults_cli_mount");
  const auto synth = runCommand(kTool + " synth --out " + dir + "/drive --scene corridor --stress drive --seed 37" +
                                " --width 320 --height 240 --fx 240.6 --fy 240 --threads 1 --overwrite" +
                                " --odom-mount-error -1.5,-1,1,0.02,0.02,-0.02");
  INFO(synth.output);
  REQUIRE(synth.exitCode == 0);
  const sb::Trajectory truth = sb::readTumTrajectory(dir + "/drive/groundtruth.txt");
  REQUIRE(truth.size() == kMountFrames);
  std::ofstream(dir + "/exact.json") << R"({"odometry": {"mount_sigma_deg": 0}})";
  const std::string knobs = " --controller default --threads 1 --quiet";

  const auto exact = runCommand(kTool + " run " + dir + "/drive --out " + dir + "/exact --config " + dir +
                                "/exact.json" + knobs);
  INFO(exact.output);
  REQUIRE(exact.exitCode == 0);
  const Verdict held = judge(dir + "/exact", truth, 0.5);
  CHECK(held.goodOff > 0);  // the fault is one the exact mount does not survive

  const auto sigma = runCommand(kTool + " run " + dir + "/drive --out " + dir + "/sigma" + knobs);
  INFO(sigma.output);
  REQUIRE(sigma.exitCode == 0);
  const Verdict anchored = judge(dir + "/sigma", truth, 0.5);
  INFO("worst good frame " << anchored.worstGoodM << " m (mount exact: " << held.worstGoodM << " m)");
  CHECK(anchored.goodOff == 0);
  const nlohmann::json odometry = sb::test::readJson(dir + "/sigma/summary.json").at("odometry");
  INFO(odometry.dump());
  CHECK(odometry.at("mount_learnt_from") == "floor");
  CHECK(odometry.at("mount_error_deg").get<double>() == Approx(1.80).margin(0.25));
}

TEST_CASE("wrong wheels the view can take over from: every frame posed, none good off, the wheels slipping",
          "[odometry][system]") {
  // Reversed wheels under `adaptive` (tracking every third frame): the frames between followed the wheels backwards,
  // ICP from their prediction failed or settled along the corridor's axis where they put it, and the run was lost
  // (before 2026-12-07: 125 of 360 frames lost). Now a frame in doubt is tracked from the view's own motion too and
  // the map decides (odometry/motion_model.h trackFromViewMotion). A gyro biased by 20 deg/s under DEFAULT: each
  // frame's error under one frame's gate, fused frame after frame until the view was lost (81 frames); now the view's
  // corrections summed over a second find it (odometry/wheel_faults.h TurnCorrections).
  const std::string dir = sb::test::scratchDir("test_wheel_faults_cli_wrong");
  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {"reversed", "--seed 47 --odom-wrong reversed,3,6", "adaptive"},
      {"gyro", "--seed 48 --odom-wrong gyro,3,6,20", "default"}};
  constexpr int kWrongFrames = 360;
  for (const auto& [name, fault, controller] : cases) {
    const std::string seq = dir + "/" + name;
    const auto synth = runCommand(kTool + " synth --out " + seq + " --scene corridor --stress drive --frames " +
                                  std::to_string(kWrongFrames) +
                                  " --width 320 --height 240 --fx 240.6 --fy 240 --threads 1 --overwrite " + fault);
    INFO(synth.output);
    REQUIRE(synth.exitCode == 0);
    const sb::Trajectory truth = sb::readTumTrajectory(seq + "/groundtruth.txt");
    REQUIRE(truth.size() == kWrongFrames);
    const auto run = runCommand(kTool + " run " + seq + " --out " + seq + "-run --controller " + controller +
                                " --threads 1 --quiet");
    INFO(run.output);
    REQUIRE(run.exitCode == 0);
    const Verdict v = judge(seq + "-run", truth);
    INFO(name << ": worst good frame " << v.worstGoodM << " m, " << v.unposed << " frames lost");
    CHECK(v.goodOff == 0);
    CHECK(v.unposed <= kWrongFrames / 20);  // at least 95% posed
    CHECK(v.slipping > 0);
  }
}

TEST_CASE("wheels withheld facing the end wall: the camera keeps the base's height", "[odometry][system]") {
  // Wheels reading twice the distance from 6 s for 10 s under `adaptive`: found slipping and withheld, and at the
  // corridor's end (frames 440-465) the view faces the end wall, whose structure leaves the height free
  // (conditioning 0.0002-0.0006). The view alone slid 0.27 m down there and the map grew at that height: for the
  // rest of the drive 371 `good` frames were 0.3 m off (before 2026-12-07). A base on its floor keeps its height
  // whatever its wheels read: ICP's solve now weighs it (odometry.planar_prior_conditioning).
  const std::string dir = sb::test::scratchDir("test_wheel_faults_cli_height");
  constexpr int kHeightFrames = 500;
  const auto synth = runCommand(kTool + " synth --out " + dir + "/drive --scene corridor --stress drive --seed 44 --frames " +
                                std::to_string(kHeightFrames) +
                                " --width 320 --height 240 --fx 240.6 --fy 240 --threads 1 --overwrite"
                                " --odom-wrong scaled,6,10,2");
  INFO(synth.output);
  REQUIRE(synth.exitCode == 0);
  const sb::Trajectory truth = sb::readTumTrajectory(dir + "/drive/groundtruth.txt");
  REQUIRE(truth.size() == kHeightFrames);
  const auto run = runCommand(kTool + " run " + dir + "/drive --out " + dir + "/run --controller adaptive --threads 1 --quiet");
  INFO(run.output);
  REQUIRE(run.exitCode == 0);
  double worstHeightM = 0.0;  // the synthetic world's y is vertical
  int slipping = 0, posed = 0;
  for (const sb::test::AnchoredFrame& f : sb::test::anchoredFrames(dir + "/run", truth)) {
    if (f.state == "lost") continue;
    ++posed;
    worstHeightM = std::max(worstHeightM, std::abs(f.error.y()));
    const auto& o = f.line.at("odometry");
    slipping += o.contains("fault") && o.at("fault").get<std::string>() == "slipping";
  }
  INFO("worst height error " << worstHeightM << " m over " << posed << " posed frames, " << slipping << " slipping");
  CHECK(slipping > 100);  // the wheels were withheld through the end wall
  CHECK(posed >= kHeightFrames * 95 / 100);
  CHECK(worstHeightM < 0.1);
}

TEST_CASE("wheels reading zero while the robot drives on: no dispute ends on a frame that could not settle it",
          "[odometry][system]") {
  // Wheels reading zero from 13 s for 10 s (the whole drive, `adaptive`). The view discarded each frame as breaking the
  // body's inertia (the last velocity was the wheels' nil one) while the pose stood with the wheels, and the dispute
  // ended on frames that settled nothing: three tracked from the wheels' prediction where the view barely fixed the
  // corridor's axis (ICP stayed where it started: no disagreement), and three counted in a row across a view discarded
  // between them. Three `good` frames 0.30-0.62 m off (before 2026-12-08). Now only a view that fixes the motion the
  // dispute is about settles it, and a discarded view breaks the run of agreeing frames (odometry/wheel_faults.h).
  const std::string dir = sb::test::scratchDir("test_wheel_faults_cli_zero");
  const auto synth = runCommand(kTool + " synth --out " + dir + "/drive --scene corridor --stress drive --seed 42" +
                                " --width 320 --height 240 --fx 240.6 --fy 240 --threads 1 --overwrite"
                                " --odom-wrong zero,13,10");
  INFO(synth.output);
  REQUIRE(synth.exitCode == 0);
  const sb::Trajectory truth = sb::readTumTrajectory(dir + "/drive/groundtruth.txt");
  const auto run = runCommand(kTool + " run " + dir + "/drive --out " + dir + "/run --controller adaptive --threads 1 --quiet");
  INFO(run.output);
  REQUIRE(run.exitCode == 0);
  const Verdict v = judge(dir + "/run", truth);
  INFO("worst good frame " << v.worstGoodM << " m, " << v.unposed << " frames lost");
  CHECK(v.goodOff == 0);
}
