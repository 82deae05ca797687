// A bag's wheel odometry (issue 41's bag door): nav_msgs/Odometry on /odom composed with the camera mount
// from /tf_static (or --camera-mount) gives `slambooster run FILE.bag` and the daemon's replay of the bag the
// samples of the drive's odometry.txt, and the same trajectory as the drive's TUM directory.

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>

#include "report/run_summary.h"
#include "tests/daemon/daemon_e2e.h"
#include "tests/ros/bag_writer.h"
#include "tests/ros/ros_fixture.h"

namespace {

using namespace sb::test;
using namespace sb::test::ros_e2e;
using sb::test::e2e::kDaemon;
using sb::test::e2e::kTool;

constexpr int kDriveFrames = 60;
std::string config;  // the pipeline config of every run

std::string lines(const std::string& path) {
  std::string out;
  for (const auto& line : trajectoryLines(path)) out += line + "\n";
  return out;
}

sb::RunSummary runTool(const std::string& input, const std::string& out, const std::string& extra = "") {
  const auto r = runCommand(kTool + " run " + input + " --out " + out + " --config " + config + " --controller fixed --threads 1 --quiet " +
                            extra + " 2>&1");
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  return sb::readRunSummary(out + "/summary.json");
}

void sameSamples(const sb::RunSummary& a, const sb::RunSummary& b) {
  REQUIRE(a.odometry);
  REQUIRE(b.odometry);
  CHECK(a.odometry->samples == b.odometry->samples);
  CHECK(a.odometry->framesWithPose == b.odometry->framesWithPose);
  CHECK(std::abs(a.odometry->pathM - b.odometry->pathM) < 1e-9);
}

}  // namespace

TEST_CASE("a bag's odometry reaches the run as the directory's odometry.txt does", "[ros][bag][odometry]") {
  const std::string dir = scratchDir("ros_bag_odometry");
  const std::string drive = dir + "/drive";
  const auto synth = runCommand(kTool + " synth --scene corridor --stress drive --seed 1 --frames " +
                                std::to_string(kDriveFrames) +
                                " --width 160 --height 120 --fx 120 --fy 120 --threads 1 --overwrite --out " + drive);
  INFO(synth.output);
  REQUIRE(synth.exitCode == 0);
  // The bag has no calibration.json: both read the directory's volume hints from one config.
  config = pipelineConfigWithHints(dir, drive);
  const sb::RunSummary fromDir = runTool(drive, dir + "/dir");
  REQUIRE(fromDir.odometry);

  BagSpec spec;
  spec.odometryFile = drive + "/odometry.txt";
  const std::string bag = dir + "/drive.bag";
  REQUIRE(writeBag(bag, drive, spec) == static_cast<size_t>(kDriveFrames));

  SECTION("the mount from /tf_static; tool and daemon") {
    const sb::RunSummary fromBag = runTool(bag, dir + "/bag");
    sameSamples(fromBag, fromDir);
    CHECK(fromBag.odometry->source.find("/odom") != std::string::npos);
    CHECK(fromBag.odometry->source.find("/tf_static base_link -> openni_depth_optical_frame") != std::string::npos);
    CHECK(lines(dir + "/bag/trajectory.tum") == lines(dir + "/dir/trajectory.tum"));
    ChildProcess d({kDaemon, "--input", bag, "--out", dir + "/daemon", "--socket", dir + "/d.sock", "--pacing", "fast",
                    "--at-end", "exit", "--set", "slam.threads=1", "--set", "slam.pipeline_config=" + config,
                    "--controller", "fixed"},
                   {}, dir + "/daemon.log");
    REQUIRE(d.wait(120.0) == 0);
    INFO(d.log());
    sameSamples(sb::readRunSummary(dir + "/daemon/summary.json"), fromDir);
  }
  SECTION("no /tf_static: --camera-mount, or an error that says to give it") {
    spec.tfStatic = false;
    const std::string bare = dir + "/bare.bag";
    writeBag(bare, drive, spec);
    sameSamples(runTool(bare, dir + "/mount", std::string("--camera-mount \"") + kBagCameraMount + "\""), fromDir);
    const auto r = runCommand(kTool + " run " + bare + " --out " + dir + "/fail --quiet 2>&1");
    CHECK(r.exitCode == 1);
    CHECK(r.output.find("--camera-mount") != std::string::npos);
    const auto none = runTool(bare, dir + "/none", "--no-odometry");
    CHECK_FALSE(none.odometry);
  }
  // Issue 53 finding 4: a zero quaternion was normalised to identity (a base that never turns) where
  // odometry.txt and ?ODOM refuse it; one rule at every door.
  SECTION("a zero quaternion in the Odometry or in /tf_static is refused, naming it") {
    spec.zeroOdometryQuaternion = true;
    const std::string zeroOdom = dir + "/zero-odom.bag";
    writeBag(zeroOdom, drive, spec);
    const auto r = runCommand(kTool + " run " + zeroOdom + " --out " + dir + "/zero-odom --quiet 2>&1");
    INFO(r.output);
    CHECK(r.exitCode == 1);
    CHECK(r.output.find("quaternion") != std::string::npos);
    CHECK(r.output.find("/odom") != std::string::npos);
    spec.zeroOdometryQuaternion = false;
    spec.zeroMountQuaternion = true;
    const std::string zeroMount = dir + "/zero-mount.bag";
    writeBag(zeroMount, drive, spec);
    const auto m = runCommand(kTool + " run " + zeroMount + " --out " + dir + "/zero-mount --quiet 2>&1");
    INFO(m.output);
    CHECK(m.exitCode == 1);
    CHECK(m.output.find("/tf_static") != std::string::npos);
    CHECK(m.output.find("quaternion") != std::string::npos);
    // And a --camera-mount far away or with a zero quaternion, as source.camera_mount.
    for (const std::string mount : {"0 0 1e300 -0.5 0.5 -0.5 0.5", "0 0 1.25 0 0 0 0"}) {
      const auto c = runCommand(kTool + " run " + bag + " --out " + dir + "/bad-mount --quiet --camera-mount \"" +
                                mount + "\" 2>&1");
      INFO(c.output);
      CHECK(c.exitCode == 1);
      CHECK(c.output.find("--camera-mount") != std::string::npos);
    }
  }
  SECTION("a topic that is not Odometry") {
    const auto r = runCommand(kTool + " run " + bag + " --out " + dir + "/fail --quiet --odom-topic " +
                              kBagDepthTopic + " 2>&1");
    CHECK(r.exitCode == 1);
    CHECK(r.output.find("nav_msgs/Odometry") != std::string::npos);
  }
}
