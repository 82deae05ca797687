// One set of bounds for every camera door and the stamps trajectory.tum can keep (drivers/camera_bounds.h,
// drivers/stamp_gate.h, issue 44 P7, G3, P8, G4).

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "drivers/camera_bounds.h"
#include "drivers/stamp_gate.h"

using namespace sb;

TEST_CASE("camera bounds: size, intrinsics and depth scale, one message shape", "[drivers][bounds]") {
  const Intrinsics good{320, 240, 240.f, 240.f, 159.5f, 119.5f};
  CHECK_FALSE(cameraOutOfBounds(good, 1000.0));
  CHECK_NOTHROW(checkCameraBounds("here", good, 5000.0, 320 * 240));
  const auto refused = [&](Intrinsics k, double scale, size_t maxPixels = 0) {
    const auto b = cameraOutOfBounds(k, scale, maxPixels);
    REQUIRE(b);
    return cameraBoundMessage("door", *b, k);
  };
  Intrinsics k = good;
  k.width = k.height = 2;
  CHECK(refused(k, 1000) == "door: width = 2 pixels is not plausible for a 2x2 image; expected width in [8, 4096] "
                            "(the pipeline's 3-level pyramid needs 8, allocations are bounded at 4096)");
  k = good;
  k.fx = std::numeric_limits<float>::infinity();
  CHECK_THAT(refused(k, 1000), Catch::StartsWith("door: fx = inf pixels is not plausible for a 320x240 image"));
  k = good;
  k.fy = 1e-30f;
  CHECK_THAT(refused(k, 1000), Catch::Contains("fy = 1e-30 pixels"));
  k = good;
  k.cx = 1e30f;
  CHECK_THAT(refused(k, 1000), Catch::Contains("cx = 1e+30 pixels") && Catch::Contains("[-320, 640]"));
  k = good;
  k.cy = std::nanf("");
  CHECK_THAT(refused(k, 1000), Catch::Contains("cy = nan"));
  CHECK_THAT(refused(good, 1e-300), Catch::Contains("depth_scale = 1e-300 raw units per metre"));
  CHECK_THAT(refused(good, 1000, 1000), Catch::Contains("width x height = 76800 pixels"));
  CHECK_THROWS_WITH(checkCameraBounds("door", good, 0.0), Catch::Contains("depth_scale = 0"));
}

TEST_CASE("stamp gate: as trajectory.tum's reader takes stamps back", "[drivers][stamps]") {
  StampGate gate;
  CHECK_FALSE(gate.check(1.0));
  CHECK_THAT(*gate.check(1.0), Catch::Contains("does not increase"));
  CHECK_THAT(*gate.check(1.0000004), Catch::Contains("does not increase"));  // the same microsecond
  CHECK(gate.check(0.5));
  CHECK_THAT(*gate.check(1e300), Catch::Contains("outside [0, 1e+10] s"));
  CHECK(gate.check(-1.0));
  CHECK(gate.check(std::numeric_limits<double>::quiet_NaN()));
  CHECK_FALSE(gate.check(1.000001));
  CHECK(gate.refused() == 6);
}
