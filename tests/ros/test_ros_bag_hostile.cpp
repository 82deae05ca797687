// Hostile bags (issue 44) through `slambooster run` and slamboosterd's replay: a CameraInfo whose K is inf,
// 1e300 or 1e-30 is refused as calibration.json is (G3: the bounds every camera door shares, one message
// shape); depth stamps that repeat, go back or repeat within a microsecond are dropped with a warning (G4),
// so the trajectory.tum of either is one `slambooster eval` reads back.

#include <cmath>
#include <filesystem>
#include <limits>

#include "drivers/sequence.h"
#include "tests/daemon/daemon_e2e.h"
#include "tests/ros/bag_writer.h"
#include "tests/ros/ros_fixture.h"

namespace {

using namespace sb::test;
using namespace sb::test::ros_e2e;
using sb::test::e2e::fixture;
using sb::test::e2e::kDaemon;
using sb::test::e2e::kTool;
using sb::test::e2e::TempDir;

// The daemon replaying `bag` to its end; its exit code, its log in `log`.
int replay(const std::string& bag, const std::string& out, const std::string& config, std::string& log) {
  TempDir tmp;  // the socket's directory (short path)
  ChildProcess d({kDaemon, "--input", bag, "--out", out, "--socket", tmp.path + "/s.sock", "--pacing", "fast",
                  "--at-end", "exit", "--set", "slam.pipeline_config=" + config, "--set", "slam.threads=1",
                  "--controller", "fixed"},
                 {}, out + "-log.txt");
  const int code = d.wait(120.0);
  log = d.log();
  return code;
}

std::vector<double> sequenceStamps(const std::string& sequence) {
  sb::SequenceOptions o;
  o.prefetch = false;
  auto source = sb::openSequence(sequence, o);
  std::vector<double> stamps;
  while (auto f = source->next()) stamps.push_back(f->timestamp);
  return stamps;
}

}  // namespace

TEST_CASE("a bag's CameraInfo out of bounds is refused like calibration.json (G3)", "[ros][bag]") {
  const auto& seq = fixture();
  const std::string dir = scratchDir("ros_bag_hostile_k");
  const std::string config = pipelineConfigWithHints(dir, seq.sequence);
  int n = 0;
  for (const double fx : {std::numeric_limits<double>::infinity(), 1e300, 1e-30}) {
    INFO("fx " << fx);
    const std::string bag = dir + "/k" + std::to_string(++n) + ".bag";
    BagSpec spec;
    spec.cameraInfoFx = fx;
    writeBag(bag, seq.sequence, spec);
    // run: an error naming the door and the value, as calibration.json's (before: exit 0, 0 frames tracked).
    const auto r = runCommand(kTool + " run " + bag + " --out " + dir + "/run" + std::to_string(n) +
                              " --config " + config + " --threads 1 --quiet 2>&1");
    INFO(r.output);
    CHECK(r.exitCode == 1);
    CHECK(r.output.find("(its CameraInfo)") != std::string::npos);
    CHECK(r.output.find("pixels is not plausible for a 320x240 image; expected fx in") != std::string::npos);
    // The daemon's replay of the bag: the same error, an error exit (not a signal).
    std::string log;
    const int code = replay(bag, dir + "/daemon" + std::to_string(n), config, log);
    INFO(log);
    CHECK(code > 0);
    CHECK(log.find("pixels is not plausible for a 320x240 image; expected fx in") != std::string::npos);
  }
}

TEST_CASE("a bag's stamps that repeat or go back are dropped; eval reads the trajectory back (G4)",
          "[ros][bag]") {
  const auto& seq = fixture();
  const std::string dir = scratchDir("ros_bag_hostile_stamps");
  const std::string config = pipelineConfigWithHints(dir, seq.sequence);
  std::vector<double> stamps = sequenceStamps(seq.sequence);
  REQUIRE(stamps.size() == size_t(e2e::kFrames));
  stamps[5] = stamps[4];           // equal
  stamps[10] = stamps[8] - 0.001;  // back in time
  stamps[14] = std::round(stamps[14] * 1e6) * 1e-6;
  stamps[15] = stamps[14] + 3e-7;  // later, but the same microsecond in trajectory.tum
  const std::string bag = dir + "/stamps.bag";
  BagSpec spec;
  spec.stamps = stamps;
  REQUIRE(writeBag(bag, seq.sequence, spec) == stamps.size());
  const std::string groundTruth = seq.sequence + "/groundtruth.txt";
  REQUIRE(std::filesystem::exists(groundTruth));
  const auto evaluates = [&](const std::string& trajectory) {
    const auto e = runCommand(kTool + " eval " + trajectory + " " + groundTruth + " --json 2>&1");
    INFO(e.output);
    CHECK(e.exitCode == 0);
    CHECK(trajectoryLines(trajectory).size() == stamps.size() - 3);
  };
  SECTION("slambooster run") {
    const auto r =
        runCommand(kTool + " run " + bag + " --out " + dir + "/run --config " + config + " --threads 1 2>&1");
    INFO(r.output);
    CHECK(r.exitCode == 0);
    CHECK(r.output.find("frame 5 dropped: its stamp") != std::string::npos);
    evaluates(dir + "/run/trajectory.tum");
  }
  SECTION("slamboosterd's replay") {
    std::string log;
    const int code = replay(bag, dir + "/daemon", config, log);
    INFO(log);
    CHECK(code == 0);
    CHECK(log.find("frame 5 dropped: its stamp") != std::string::npos);
    evaluates(dir + "/daemon/trajectory.tum");
  }
}
