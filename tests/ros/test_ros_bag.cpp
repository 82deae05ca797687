// ROS bags through the bag plugin: `slambooster run FILE.bag` and slamboosterd's replay of a bag give the
// trajectory of the same frames from a TUM directory, bit for bit (32FC1 metres and 16UC1 millimetres); bad
// bags are refused with an error naming the topic or file, and nothing crashes.

#include <filesystem>
#include <fstream>

#include "drivers/sequence.h"
#include "tests/ros/bag_writer.h"
#include "tests/daemon/daemon_e2e.h"
#include "tests/ros/ros_fixture.h"

namespace {

namespace fs = std::filesystem;
using namespace sb::test;
using namespace sb::test::ros_e2e;
using sb::test::e2e::fixture;
using sb::test::e2e::kDaemon;
using sb::test::e2e::kTool;

// The trajectory's data lines, byte for byte (the comment line names the input, which differs).
std::string slurp(const std::string& path) {
  std::string out;
  for (const auto& line : trajectoryLines(path)) out += line + "\n";
  return out;
}

std::string runTool(const std::string& input, const std::string& out, const std::string& config,
                    const std::string& extra = "") {
  const auto r = runCommand(kTool + " run " + input + " --out " + out + " --config " + config +
                            " --threads 1 --quiet " + extra + " 2>&1");
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  return slurp(out + "/trajectory.tum");
}

std::string runDaemon(const std::string& input, const std::string& dir, const std::string& name,
                      const std::string& config) {
  const std::string out = dir + "/" + name;
  ChildProcess d({kDaemon, "--input", input, "--out", out, "--socket", dir + "/" + name + ".sock", "--pacing",
                  "fast", "--at-end", "exit", "--set", "slam.pipeline_config=" + config, "--set", "slam.threads=1",
                  "--controller", "fixed"},
                 {}, dir + "/" + name + ".log");
  const int code = d.wait(120.0);
  INFO(d.log());
  REQUIRE(code == 0);
  return slurp(out + "/trajectory.tum");
}

// A failed `slambooster run`: exit code 1 (an error, not a signal) and the message.
std::string failingRun(const std::string& bag, const std::string& dir, const std::string& extra = "") {
  const auto r = runCommand(kTool + " run " + bag + " --out " + dir + "/fail --quiet " + extra + " 2>&1");
  INFO(r.output);
  CHECK(r.exitCode == 1);
  return r.output;
}

TEST_CASE("a bag replays bit for bit like the TUM directory of the same frames", "[ros][bag]") {
  const auto& seq = fixture();
  const std::string dir = scratchDir("ros_bag_equal");
  const std::string config = pipelineConfigWithHints(dir, seq.sequence);

  SECTION("32FC1 metres, the depth topic found by its encoding beside an RGB topic; tool and daemon") {
    const std::string bag = dir + "/seq32.bag";
    REQUIRE(writeBag(bag, seq.sequence, {}) == static_cast<size_t>(e2e::kFrames));
    const std::string fromDir = runTool(seq.sequence, dir + "/dir", config);
    REQUIRE(!fromDir.empty());
    CHECK(runTool(bag, dir + "/bag", config) == fromDir);
    CHECK(runDaemon(bag, dir, "daemon_bag", config) == runDaemon(seq.sequence, dir, "daemon_dir", config));
  }
  SECTION("16UC1 millimetres, the depth topic named") {
    const std::string mm = dir + "/mm";
    fs::remove_all(mm);
    writeMillimetreCopy(seq.sequence, mm);
    const std::string bag = dir + "/seq16.bag";
    BagSpec millimetres;
    millimetres.encoding = "16UC1";
    writeBag(bag, mm, millimetres);
    const std::string fromDir = runTool(mm, dir + "/mmdir", config);
    REQUIRE(!fromDir.empty());
    CHECK(runTool(bag, dir + "/mmbag", config, std::string("--depth-topic ") + kBagDepthTopic) == fromDir);
  }
}

TEST_CASE("bad bags get an error naming the topic or file, and nothing crashes", "[ros][bag]") {
  const auto& seq = fixture();
  const std::string dir = scratchDir("ros_bag_bad");
  const std::string bag = dir + "/good.bag";
  writeBag(bag, seq.sequence, {});

  SECTION("a depth topic the bag does not have") {
    const auto out = failingRun(bag, dir, "--depth-topic /camera/nope");
    CHECK(out.find("/camera/nope") != std::string::npos);
    CHECK(out.find(bag) != std::string::npos);
    CHECK(out.find(kBagDepthTopic) != std::string::npos);  // the image topics it does have
  }
  SECTION("a topic of another encoding") {
    const auto out = failingRun(bag, dir, std::string("--depth-topic ") + kBagRgbTopic);
    CHECK(out.find("rgb8") != std::string::npos);
    CHECK(out.find(kBagRgbTopic) != std::string::npos);
  }
  SECTION("no camera_info") {
    const std::string noInfo = dir + "/noinfo.bag";
    BagSpec withoutInfo;
    withoutInfo.cameraInfo = false;
    writeBag(noInfo, seq.sequence, withoutInfo);
    const auto out = failingRun(noInfo, dir);
    CHECK(out.find("/camera/depth/camera_info") != std::string::npos);
  }
  SECTION("a truncated file, for the tool and the daemon") {
    const std::string cut = dir + "/truncated.bag";
    fs::copy_file(bag, cut, fs::copy_options::overwrite_existing);
    fs::resize_file(cut, fs::file_size(cut) / 2);
    const auto out = failingRun(cut, dir);
    CHECK(out.find(cut) != std::string::npos);
    ChildProcess d({kDaemon, "--input", cut, "--out", dir + "/dfail", "--socket", dir + "/d.sock", "--pacing",
                    "fast", "--at-end", "exit"},
                   {}, dir + "/daemon_truncated.log");
    const int code = d.wait(60.0);
    INFO(d.log());
    CHECK(code > 0);  // an error exit, not a signal
    CHECK(d.log().find(cut) != std::string::npos);
  }
}

}  // namespace
