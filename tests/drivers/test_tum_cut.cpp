// Cutting a TUM-layout sequence by a frame list (drivers/tum_cut.h): the cut reads back the source's frames
// in the listed order at new, evenly spaced timestamps, with the matching reference poses; and on the shared
// 7-Scenes excerpt, the kidnap 0-299,100-199 jumps back to a place seen 200 frames earlier.

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "core/trajectory.h"
#include "drivers/sequence.h"
#include "drivers/tum_cut.h"
#include "tests/drivers/fixtures.h"
#include "tests/support/test_data.h"

using namespace sb;
namespace fs = std::filesystem;

namespace {

// Source frame i's reference pose: 0.1 i metres along x, yawed 10 i degrees about y.
TimedPose sourcePose(size_t i) {
  TimedPose p;
  p.timestamp = 100.0 + 0.1 * static_cast<double>(i);
  p.T_camera_to_world.linear() =
      Eigen::AngleAxisd(static_cast<double>(i) * 10.0 * 3.141592653589793 / 180.0, Eigen::Vector3d::UnitY())
          .toRotationMatrix();
  p.T_camera_to_world.translation() = Eigen::Vector3d(0.1 * static_cast<double>(i), 0.0, 0.0);
  return p;
}

std::string writeSourceWithTruth(const std::string& dir, size_t frames) {
  test::writePatternSequence(dir, frames, test::smallInfo());
  Trajectory truth;
  for (size_t i = 0; i < frames; ++i) truth.push_back(sourcePose(i));
  writeTumTrajectory(dir + "/groundtruth.txt", truth);
  return dir;
}

SequenceOptions direct() {
  SequenceOptions o;
  o.prefetch = false;
  return o;
}

}  // namespace

TEST_CASE("frame lists parse ranges and single frames, and reject malformed ones", "[drivers][cut]") {
  const std::vector<FrameRange> r = parseFrameList("0-299, 100-199,7");
  REQUIRE(r.size() == 3);
  CHECK((r[0].first == 0 && r[0].last == 299));
  CHECK((r[1].first == 100 && r[1].last == 199));
  CHECK((r[2].first == 7 && r[2].last == 7));
  for (const char* bad : {"", "5-3", "a-4", "-3", "1-", "1,,2", "1,", "1-2-3", "+4"}) {
    INFO("'" << bad << "'");
    CHECK_THROWS_AS(parseFrameList(bad), Error);
  }
}

TEST_CASE("a cut reads back the listed source frames at new timestamps with their reference poses",
          "[drivers][cut]") {
  const std::string scratch = test::scratchDir("tum_cut");
  const std::string src = writeSourceWithTruth(scratch + "/src", 6);
  const std::string out = scratch + "/cut";
  const CutResult r = cutTumSequence(src, parseFrameList("0-4,1-2"), out);
  CHECK(r.frames == 7);
  CHECK(r.groundTruthPoses == 7);
  CHECK(r.frameIntervalS == Approx(0.1));
  REQUIRE(r.jumps.size() == 1);
  CHECK(r.jumps[0].frame == 5);
  CHECK(r.jumps[0].fromSource == 4);
  CHECK(r.jumps[0].toSource == 1);
  CHECK(r.jumps[0].translationM == Approx(0.3));
  CHECK(r.jumps[0].rotationDeg == Approx(30.0));
  // Nothing copied: no depth images in the cut, its index names the source's.
  CHECK_FALSE(fs::exists(out + "/depth"));
  CHECK(test::readText(out + "/calibration.json") == test::readText(src + "/calibration.json"));
  CHECK(test::readText(out + "/segments.csv") == "label,begin_frame,end_frame\nsrc-0-4,0,5\nsrc-1-2,5,7\n");

  const size_t sourceFrames[] = {0, 1, 2, 3, 4, 1, 2};
  auto cut = openSequence(out, direct());
  CHECK(cut->info().frameCount == 7);
  CHECK(cut->info().intrinsics.fx == 5.5f);
  const Trajectory truth = readTumTrajectory(cut->info().groundTruthPath);
  REQUIRE(truth.size() == 7);
  for (size_t k = 0; k < 7; ++k) {
    INFO("cut frame " << k);
    const auto f = cut->next();
    REQUIRE(f);
    CHECK(f->timestamp == Approx(100.0 + 0.1 * static_cast<double>(k)));
    CHECK(f->depth.pixels() == test::patternDepth(sourceFrames[k], 6, 4).pixels());
    CHECK(truth[k].timestamp == Approx(f->timestamp).margin(1e-6));
    CHECK(truth[k].T_camera_to_world.isApprox(sourcePose(sourceFrames[k]).T_camera_to_world, 1e-6));
  }
  CHECK_FALSE(cut->next());

  // Again into the same directory: refused, unless overwriting.
  CHECK_THROWS_AS(cutTumSequence(src, parseFrameList("0-1"), out), Error);
  CHECK(cutTumSequence(src, parseFrameList("0-1"), out, CutOptions{true}).frames == 2);
  CHECK(openSequence(out, direct())->info().frameCount == 2);
}

TEST_CASE("a cut refuses frames past the source's end and an output inside the source", "[drivers][cut]") {
  const std::string scratch = test::scratchDir("tum_cut_errors");
  const std::string src = writeSourceWithTruth(scratch + "/src", 4);
  try {
    cutTumSequence(src, parseFrameList("0-4"), scratch + "/cut");
    FAIL("a frame past the end was accepted");
  } catch (const Error& e) {
    CHECK(std::string(e.what()).find("frame 4 is past the end") != std::string::npos);
  }
  CHECK_THROWS_AS(cutTumSequence(src, parseFrameList("0-1"), src + "/cut"), Error);
}

TEST_CASE("7-Scenes kidnap 0-299,100-199: a jump back to a place seen 200 frames earlier",
          "[data][drivers][cut]") {
  const std::string sub = "7scenes-redkitchen-a";
  REQUIRE(test::hasSharedData(sub));
  const std::string src = test::sharedDataDir() + "/" + sub;
  const std::string out = test::scratchDir("tum_cut_7scenes") + "/kidnap";
  const CutResult r = cutTumSequence(src, parseFrameList("0-299,100-199"), out);
  CHECK(r.frames == 400);
  CHECK(r.groundTruthPoses == 400);
  CHECK(r.frameIntervalS == Approx(1.0 / 30).epsilon(1e-3));
  REQUIRE(r.jumps.size() == 1);
  // Measured on the excerpt: 0.79 m and 35 degrees between source frames 299 and 100.
  CHECK(r.jumps[0].translationM == Approx(0.788).margin(0.005));
  CHECK(r.jumps[0].rotationDeg == Approx(34.9).margin(0.5));
  auto cut = openSequence(out);
  CHECK(cut->info().format == "7scenes");
  CHECK(cut->info().frameCount == 400);
  const Trajectory truth = readTumTrajectory(cut->info().groundTruthPath);
  const Trajectory source = readTumTrajectory(src + "/groundtruth.txt");
  REQUIRE(truth.size() == 400);
  CHECK(truth[300].T_camera_to_world.isApprox(source[100].T_camera_to_world, 1e-6));
  CHECK(truth[399].timestamp == Approx(399.0 / 30).margin(1e-5));
}
