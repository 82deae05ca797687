// writeIteCsv(): one line per matched frame with the aligned and unaligned errors, readable back exactly.

#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>
#include <string>

#include "core/error.h"
#include "eval/trajectory_eval.h"
#include "tests/eval/eval_test_util.h"
#include "tests/support/test_data.h"

TEST_CASE("the ITE CSV holds every matched frame's errors", "[eval][ite]") {
  const auto gt = sb::test::helixTrajectory(40);
  auto est = gt;
  for (size_t i = 0; i < est.size(); ++i) est[i].T_camera_to_world.translation().z() += 0.001 * (i % 5);
  const auto ate = sb::computeAte(est, gt);
  const std::string path = sb::test::scratchDir("eval_ite_csv") + "/ite.csv";
  sb::writeIteCsv(path, ate);

  std::ifstream in(path);
  std::string line;
  REQUIRE(std::getline(in, line));
  CHECK(line == "timestamp,ate_error_m,unaligned_error_m");
  size_t rows = 0;
  while (std::getline(in, line)) {
    REQUIRE(rows < ate.errors.size());
    std::istringstream ss(line);
    double t, e, u;
    char c1, c2;
    REQUIRE((ss >> t >> c1 >> e >> c2 >> u));
    CHECK(t == Approx(ate.timestamps[rows]).margin(1e-6));
    CHECK(e == Approx(ate.errors[rows]).margin(1e-9));
    CHECK(u == Approx(ate.unalignedErrors[rows]).margin(1e-9));
    ++rows;
  }
  CHECK(rows == ate.errors.size());
}

TEST_CASE("the ITE CSV reports an unwritable path", "[eval][ite][errors]") {
  const auto gt = sb::test::helixTrajectory(10);
  const auto ate = sb::computeAte(gt, gt);
  CHECK_THROWS_AS(sb::writeIteCsv("/nonexistent-dir/ite.csv", ate), sb::Error);
}
