// Config and knob parsing: defaults match architecture.md D2; errors name the key, value and range.

#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "pipeline/bilateral_taps.h"
#include "pipeline/config.h"
#include "pipeline/knobs.h"

using Catch::Matchers::Contains;

TEST_CASE("config defaults are the reference constants", "[pipeline][config]") {
  const sb::PipelineConfig c;
  CHECK(c.bilateralRadius == 2);
  CHECK(c.bilateralSpatialSigma == 4.0f);
  CHECK(c.bilateralRangeSigma == 0.1f);
  CHECK(c.halfSampleMaxDifference == 0.3f);
  CHECK(c.icpDistanceThreshold == 0.1f);
  CHECK(c.icpNormalThreshold == 0.8f);
  CHECK(c.trackedMaxResidual == 0.02f);
  CHECK(c.trackedMinInliers == 0.15f);
  CHECK(c.maxWeight == 100);
  CHECK(c.nearPlane == 0.4f);
  CHECK(c.farPlane == 4.0f);
  CHECK(c.raycastLargeStep == 0.75f);
  CHECK(c.volumeResolution == 256);
  CHECK(c.volumeSize == 5.0f);
  CHECK(c.mu == 0.1f);
  CHECK(c.initialPosition == std::array<float, 3>{0.5f, 0.5f, 0.3f});
  CHECK_NOTHROW(sb::validateConfig(c));
}

TEST_CASE("config JSON round-trips and overrides fields", "[pipeline][config]") {
  sb::PipelineConfig c = sb::parseConfig(nlohmann::json::parse(
      R"({"mu_m": 0.05, "volume_resolution": 128, "initial_position": [0.4, 0.5, 0.1], "knobs": "csr=2,ir=1"})"));
  CHECK(c.mu == 0.05f);
  CHECK(c.volumeResolution == 128);
  CHECK(c.initialPosition[0] == 0.4f);
  CHECK(c.knobs.csr == 2);
  CHECK(c.knobs.integrationRate == 1);
  const sb::PipelineConfig back = sb::parseConfig(sb::configToJson(c));
  CHECK(back.mu == c.mu);
  CHECK(back.knobs == c.knobs);
}

TEST_CASE("config errors name the key, the value and the allowed range", "[pipeline][config]") {
  auto parse = [](const char* text) { return sb::parseConfig(nlohmann::json::parse(text), {}, "test.json"); };
  CHECK_THROWS_WITH(parse(R"({"mu_meters": 0.1})"), Contains("unknown key 'mu_meters'") && Contains("mu_m"));
  CHECK_THROWS_WITH(parse(R"({"mu_m": "0.1"})"), Contains("'mu_m'") && Contains("number"));
  CHECK_THROWS_WITH(parse(R"({"mu_m": -1})"), Contains("'mu_m'") && Contains("-1") && Contains("[0.0001, 10]"));
  CHECK_THROWS_WITH(parse(R"({"volume_resolution": 100})"), Contains("volume_resolution") && Contains("multiple of 8"));
  CHECK_THROWS_WITH(parse(R"({"volume_resolution": 2.5})"), Contains("volume_resolution") && Contains("integer"));
  CHECK_THROWS_WITH(parse(R"({"initial_position": [0.5, 2, 0.3]})"), Contains("initial_position") && Contains("2"));
  CHECK_THROWS_WITH(parse(R"({"near_plane_m": 5, "far_plane_m": 4})"), Contains("far_plane_m"));
  CHECK_THROWS_WITH(parse(R"({"knobs": "csr=3"})"), Contains("knobs") && Contains("csr=3"));
  CHECK_THROWS_WITH(parse("[1, 2]"), Contains("JSON object"));
}

TEST_CASE("knob presets are the D2 table of docs/architecture.md", "[pipeline][knobs]") {
  const sb::Knobs d = sb::knobPreset("default");
  CHECK(d.csr == 1);
  CHECK(d.icpThreshold == 1e-5);
  CHECK(d.pyramidIterations == std::array<int, 3>{10, 5, 4});
  CHECK(d.trackingRate == 1);
  CHECK(d.integrationRate == 2);
  const sb::Knobs a = sb::knobPreset("accurate");
  CHECK(a.icpThreshold == 0.0);
  CHECK(a.integrationRate == 1);
  CHECK_THROWS_WITH(sb::knobPreset("fast"), Contains("fast") && Contains("accurate"));
}

TEST_CASE("knob strings parse and impossible values are rejected clearly", "[pipeline][knobs]") {
  const sb::Knobs k = sb::parseKnobs("csr=2,icp=1e-4,pd=8:5:4,tr=1,ir=2");
  CHECK(k.csr == 2);
  CHECK(k.icpThreshold == 1e-4);
  CHECK(k.pyramidIterations == std::array<int, 3>{8, 5, 4});
  CHECK(sb::parseKnobs(sb::formatKnobs(k)) == k);
  CHECK(sb::parseKnobs("ir=5", k).integrationRate == 5);
  CHECK_THROWS_WITH(sb::parseKnobs("csr=3"), Contains("csr=3") && Contains("1, 2, 4 or 8"));
  CHECK_THROWS_WITH(sb::parseKnobs("icp=-1"), Contains("icp") && Contains("[0, 1]"));
  CHECK_THROWS_WITH(sb::parseKnobs("pd=10:5"), Contains("three"));
  CHECK_THROWS_WITH(sb::parseKnobs("pd=0:5:4"), Contains("pd0=0"));
  CHECK_THROWS_WITH(sb::parseKnobs("tr=0"), Contains("tr=0"));
  CHECK_THROWS_WITH(sb::parseKnobs("ir=x"), Contains("ir") && Contains("not a number"));
  CHECK_THROWS_WITH(sb::parseKnobs("speed=3"), Contains("unknown knob 'speed'"));
  CHECK_THROWS_WITH(sb::parseKnobs("csr"), Contains("no '='"));
}

TEST_CASE("the bilateral taps: the config's radius and sigma in the image's pixels", "[config][preprocess]") {
  sb::PipelineConfig c;  // radius 2, sigma 4
  const sb::BilateralTaps full = sb::bilateralTaps(c);
  REQUIRE(full.radius == 2);
  REQUIRE(full.weights.size() == 5);
  CHECK(full.weights[1] == std::exp(-1.0f / 32.0f));
  CHECK(full.weights[2] == 1.0f);
  c.bilateralRadius = 0;  // no filter stays no filter
  CHECK(sb::bilateralTaps(c).radius == 0);
}

