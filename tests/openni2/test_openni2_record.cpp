// `slambooster record` against the test camera driver: what it writes re-reads through the TUM reader.

#include <signal.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include "drivers/sequence.h"
#include "tests/daemon/process.h"
#include "tests/openni2/room_frames.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

using sb::test::runCommand;

namespace {

const std::string kTool = SB_SLAMBOOSTER_BIN;
// The tool loads libOpenNI2 through the build tree's link, whose driver repository holds the test driver.
const std::string kEnv = std::string("LD_LIBRARY_PATH=") + SB_OPENNI2_RUNTIME + " ";

std::string record(const std::string& args) { return kEnv + kTool + " record " + args; }

std::vector<sb::DepthFrame> readAll(const std::string& dir, sb::SequenceInfo& info) {
  auto seq = sb::openSequence(dir);
  info = seq->info();
  std::vector<sb::DepthFrame> frames;
  while (auto f = seq->next()) frames.push_back(std::move(*f));
  return frames;
}

}  // namespace

TEST_CASE("record: --frames N writes N frames that re-read through the TUM reader", "[openni2][record]") {
  const std::string dir = sb::test::scratchDir("record_frames") + "/seq";
  const auto r = runCommand(record("--out " + dir + " --uri sbtest://cam --width 320 --height 240 --fps 60 --frames 12"));
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  CHECK_THAT(r.output, Catch::Contains("wrote 12 frames"));
  sb::SequenceInfo info;
  const auto frames = readAll(dir, info);
  REQUIRE(frames.size() == 12);
  CHECK(info.format == "openni2");
  CHECK(info.depthScale == 1000.0);
  CHECK(info.intrinsics.width == 320);
  CHECK(info.intrinsics.fx == Approx(sb::test::roomFx(320)).epsilon(1e-4));
  CHECK(info.intrinsics.cx == Approx(160.0));
  for (size_t i = 0; i < frames.size(); ++i) {
    CHECK(sb::test::roomMismatches(frames[i], sb::test::roomShotOf(frames[i])) == 0);
    if (i > 0) CHECK(frames[i].timestamp > frames[i - 1].timestamp);
  }
}

TEST_CASE("record: --seconds S stops after S seconds of camera time", "[openni2][record]") {
  const std::string dir = sb::test::scratchDir("record_seconds") + "/seq";
  const auto r = runCommand(record("--out " + dir + " --width 320 --height 240 --fps 60 --seconds 0.5"));
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  sb::SequenceInfo info;
  const auto frames = readAll(dir, info);
  REQUIRE(frames.size() >= 10);
  CHECK(frames.size() <= 31);  // 60 fps for 0.5 s: 30 frames span 0.483 s
  CHECK(frames.back().timestamp - frames.front().timestamp < 0.5);
}

TEST_CASE("record: a camera lost mid-recording: exit 1, the frames before are a complete sequence",
          "[openni2][record]") {
  const std::string dir = sb::test::scratchDir("record_lost") + "/seq";
  const auto r = runCommand(record("--out " + dir +
                                   " --uri 'sbtest://cam?disconnect_after=8' --width 320 --height 240 --fps 60"));
  INFO(r.output);
  CHECK(r.exitCode == 1);
  CHECK_THAT(r.output, Catch::Contains("camera was lost"));
  // The camera sends 8 frames; a recorder slowed by a loaded machine may miss one before the driver reports the
  // loss (a live camera is not waited for), so the count is what it says it kept: 1 to 8, and exactly those.
  const auto at = r.output.find(" frames before are complete");
  REQUIRE(at != std::string::npos);
  const size_t start = r.output.rfind("the ", at) + 4;
  const int kept = std::stoi(r.output.substr(start, at - start));
  CHECK(kept >= 1);
  CHECK(kept <= 8);
  sb::SequenceInfo info;
  CHECK(readAll(dir, info).size() == size_t(kept));
}

TEST_CASE("record: Ctrl-C finishes the sequence", "[openni2][record]") {
  const std::string scratch = sb::test::scratchDir("record_sigint");
  const std::string dir = scratch + "/seq";
  sb::test::ChildProcess p({kTool, "record", "--out", dir, "--width", "320", "--height", "240", "--fps", "60"},
                           {std::string("LD_LIBRARY_PATH=") + SB_OPENNI2_RUNTIME}, scratch + "/log.txt");
  REQUIRE(sb::test::waitForPath(dir + "/depth/000005.png", 20));
  p.signal(SIGINT);
  const int code = p.wait(10);
  INFO(p.log());
  CHECK(code == 0);
  sb::SequenceInfo info;
  const auto frames = readAll(dir, info);
  CHECK(frames.size() >= 6);
  CHECK_THAT(p.log(), Catch::Contains("wrote " + std::to_string(frames.size()) + " frames"));
}

TEST_CASE("record: bad requests exit non-zero and say why", "[openni2][record]") {
  const std::string scratch = sb::test::scratchDir("record_errors");
  const auto absent = runCommand(record("--out " + scratch + "/a --uri sbtest://absent --frames 3"));
  CHECK(absent.exitCode == 1);
  CHECK_THAT(absent.output, Catch::Contains("no OpenNI2 device with URI 'sbtest://absent'"));
  const auto mode = runCommand(record("--out " + scratch + "/b --width 1024 --height 768 --frames 3"));
  CHECK(mode.exitCode == 1);
  CHECK_THAT(mode.output, Catch::Contains("it offers: 640x480@30 1mm"));
  const auto both = runCommand(record("--out " + scratch + "/c --frames 3 --seconds 1"));
  CHECK(both.exitCode == 2);
  CHECK_FALSE(std::filesystem::exists(scratch + "/c"));
}
