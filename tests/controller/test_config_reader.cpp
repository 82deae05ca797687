// ConfigReader: typed, range-checked keys; every error names where, the key and the value.

#include <catch2/catch.hpp>

#include "controller/config_reader.h"
#include "controller/knob_ladder.h"
#include "core/error.h"

using Catch::Matchers::Contains;

TEST_CASE("ConfigReader reads present keys and leaves absent ones", "[controller][config]") {
  const auto j = nlohmann::json::parse(R"({"a": 0.5, "n": 3, "b": true, "s": "x", "list": [1, 2]})");
  sb::ConfigReader r(j, "file.json: section");
  double a = 0, missing = 7;
  int n = 0;
  bool b = false;
  std::string s;
  std::vector<int> list;
  r.number("a", a, 0, 1);
  r.number("missing", missing, 0, 10);
  r.integer("n", n, 0, 5);
  r.boolean("b", b);
  r.string("s", s, {"x", "y"});
  r.integers("list", list, 0, 9, 1, 4);
  REQUIRE_NOTHROW(r.finish());
  CHECK(a == 0.5);
  CHECK(missing == 7);
  CHECK(n == 3);
  CHECK(b);
  CHECK(s == "x");
  CHECK(list == std::vector<int>{1, 2});
}

TEST_CASE("ConfigReader errors name the place, the key, the value and the allowed range", "[controller][config]") {
  double x = 0;
  int n = 0;
  {
    sb::ConfigReader r(nlohmann::json::parse(R"({"gain": 5})"), "c.json: controller.slambooster");
    CHECK_THROWS_WITH(r.number("gain", x, 0, 1),
                      Contains("c.json: controller.slambooster") && Contains("'gain'") && Contains("[0, 1]"));
  }
  {
    sb::ConfigReader r(nlohmann::json::parse(R"({"gain": "high"})"), "w");
    CHECK_THROWS_WITH(r.number("gain", x, 0, 1), Contains("'gain' must be a number") && Contains("high"));
  }
  {
    sb::ConfigReader r(nlohmann::json::parse(R"({"frames": 1.5})"), "w");
    CHECK_THROWS_WITH(r.integer("frames", n, 0, 10), Contains("'frames' must be an integer"));
  }
  {
    sb::ConfigReader r(nlohmann::json::parse(R"({"gain": 0.5, "typo": 1})"), "w");
    r.number("gain", x, 0, 1);
    CHECK_THROWS_WITH(r.finish(), Contains("unknown key 'typo'") && Contains("gain"));
  }
  CHECK_THROWS_AS(sb::ConfigReader(nlohmann::json::parse("[1]"), "w"), sb::Error);
}

TEST_CASE("The knob ladder couples one level to csr, icp and pd0 as the original", "[controller][ladder]") {
  const sb::KnobLadder ladder;
  const int csr[] = {1, 2, 4, 8};
  const double icp[] = {1e-5, 1e-5, 1e-4, 1e-4};
  const int pd0[] = {10, 8, 6, 4};
  for (int level = 0; level <= 3; ++level) {
    const sb::Knobs k = ladder.coupled(level);
    CHECK(k.csr == csr[level]);
    CHECK(k.icpThreshold == icp[level]);
    CHECK(k.pyramidIterations == std::array<int, 3>{pd0[level], 5, 4});
    CHECK(k.integrationRate == 1);
    CHECK(k.trackingRate == 1);
  }
  CHECK(ladder.coupled(9) == ladder.coupled(3));
  CHECK(ladder.coupled(-1) == ladder.coupled(0));

  sb::KnobLadder bad;
  sb::ConfigReader r(nlohmann::json::parse(R"({"csr_levels": [1, 3]})"), "w");
  CHECK_THROWS_WITH(bad.read(r), Contains("csr"));
}
