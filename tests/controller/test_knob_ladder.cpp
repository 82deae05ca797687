// The knob ladder: one level couples csr, icp and pd0 as the original; its settings come from the config reader.

#include <catch2/catch.hpp>

#include "controller/knob_ladder.h"
#include "core/config_reader.h"
#include "core/error.h"

using Catch::Matchers::Contains;

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
