// [data] tests: the shared 7-Scenes red-kitchen excerpt (../shared/data/7scenes-redkitchen-a).
#include <catch2/catch.hpp>

#include "drivers/sequence.h"
#include "tests/support/test_data.h"

using namespace sb;

namespace {

// Valid readings of a Kinect v1 indoors, metres.
constexpr double kNearM = 0.4;
constexpr double kFarM = 5.0;

std::string sevenScenesDir() {
  const std::string sub = "7scenes-redkitchen-a";
  if (!test::hasSharedData(sub)) {
    WARN("shared data " << test::sharedDataDir() << "/" << sub << " is absent");
    return "";
  }
  return test::sharedDataDir() + "/" + sub;
}

}  // namespace

TEST_CASE("7-Scenes red kitchen opens with its calibration", "[data][drivers]") {
  const std::string dir = sevenScenesDir();
  REQUIRE_FALSE(dir.empty());
  auto source = openSequence(dir);
  const SequenceInfo& info = source->info();
  CHECK(info.format == "7scenes");
  CHECK(info.frameCount == 600);
  CHECK(info.intrinsics.width == 640);
  CHECK(info.intrinsics.height == 480);
  CHECK(info.intrinsics.fx == 585.f);
  CHECK(info.intrinsics.fy == 585.f);
  CHECK(info.intrinsics.cx == 320.f);
  CHECK(info.intrinsics.cy == 240.f);
  CHECK(info.depthScale == 1000.0);
  CHECK(info.groundTruthPath == dir + "/groundtruth.txt");

  const auto first = source->next();
  REQUIRE(first);
  CHECK(first->index == 0);
  CHECK(first->timestamp == 0.0);
  size_t valid = 0, plausible = 0, saturated = 0;
  for (const uint16_t v : first->depth.pixels()) {
    if (v == 65535) ++saturated;
    if (v == 0) continue;
    ++valid;
    const double metres = v / info.depthScale;
    if (metres >= kNearM && metres <= kFarM) ++plausible;
  }
  CHECK(saturated == 0);
  // Most of a kitchen view has a reading, nearly all of them in the sensor's range.
  CHECK(valid > first->depth.size() / 2);
  CHECK(plausible > valid * 9 / 10);
}

TEST_CASE("7-Scenes red kitchen reads to the end with prefetching", "[data][drivers]") {
  const std::string dir = sevenScenesDir();
  REQUIRE_FALSE(dir.empty());
  auto source = openSequence(dir);
  size_t n = 0;
  double last = -1.0;
  while (auto f = source->next()) {
    CHECK(f->index == n);
    CHECK(f->timestamp > last);
    last = f->timestamp;
    ++n;
  }
  CHECK(n == 600);
  CHECK(last == Approx(599 / 30.0).margin(1e-5));
}
