// associate(): nearest timestamps within the maximum difference, each pose used once, greedy by smallest
// difference (TUM associate.py semantics), sorted by time.

#include <catch2/catch.hpp>
#include <vector>

#include "core/error.h"
#include "eval/trajectory_eval.h"
#include "tests/eval/eval_test_util.h"

using sb::test::makePose;

namespace {

sb::Trajectory atTimes(const std::vector<double>& times) {
  sb::Trajectory t;
  for (double s : times) t.push_back(makePose(s, Eigen::Vector3d(s, 0, 0)));
  return t;
}

}  // namespace

TEST_CASE("association keeps jittered pairs and rejects those beyond the maximum difference",
          "[eval][associate]") {
  constexpr double kRateHz = 10.0;  // 0.1 s apart, so a rejected pose has no other candidate within 0.02 s
  constexpr size_t kPoses = 40;
  // Jitters (s) cycling over the poses; |j| > 0.02 must be rejected.
  const std::vector<double> jitter = {0.0, 0.019, -0.019, 0.005, -0.03, 0.021, -0.0125, 0.045};
  sb::Trajectory gt, est;
  std::vector<std::pair<size_t, size_t>> expected;
  for (size_t k = 0; k < kPoses; ++k) {
    const double t = 1000.0 + static_cast<double>(k) / kRateHz;
    gt.push_back(makePose(t, Eigen::Vector3d::Zero()));
    const double j = jitter[k % jitter.size()];
    est.push_back(makePose(t + j, Eigen::Vector3d::Zero()));
    if (std::abs(j) <= 0.02) expected.emplace_back(k, k);
  }
  const auto pairs = sb::associate(est, gt);
  REQUIRE(pairs.size() == kPoses / jitter.size() * 5);
  CHECK(pairs == expected);
}

TEST_CASE("association is greedy by smallest time difference and uses each pose once", "[eval][associate]") {
  // Candidates within 0.02 s, smallest first: (0.001, 0.000) 0.001 s, (0.010, 0.000) 0.010 s,
  // (0.012, 0.000) 0.012 s, (0.012, 0.025) 0.013 s, (0.010, 0.025) 0.015 s. Greedy acceptance takes the
  // first and the fourth: estimate 0.010 stays unmatched although ground truth 0.025 is within reach of it,
  // because estimate 0.012 is closer to that pose.
  const auto gt = atTimes({0.0, 0.025, 1.0});
  const auto est = atTimes({0.001, 0.010, 0.012});
  const auto pairs = sb::associate(est, gt);
  const std::vector<std::pair<size_t, size_t>> expected = {{0, 0}, {2, 1}};
  CHECK(pairs == expected);
}

TEST_CASE("association applies the time offset and the maximum difference option", "[eval][associate]") {
  const auto gt = atTimes({0.0, 0.1, 0.2, 0.3});
  const auto est = atTimes({100.03, 100.13, 100.23});
  CHECK(sb::associate(est, gt).empty());
  sb::AssociationOptions o;
  o.timeOffset = -100.0;
  CHECK(sb::associate(est, gt, o).empty());  // 0.03 s apart: beyond 0.02
  o.maxTimeDifference = 0.04;
  const std::vector<std::pair<size_t, size_t>> expected = {{0, 0}, {1, 1}, {2, 2}};
  CHECK(sb::associate(est, gt, o) == expected);
}

TEST_CASE("association returns pairs in time order even for unsorted input", "[eval][associate]") {
  const auto gt = atTimes({0.3, 0.1, 0.2});
  const auto est = atTimes({0.21, 0.29, 0.11});
  const std::vector<std::pair<size_t, size_t>> expected = {{2, 1}, {0, 2}, {1, 0}};
  CHECK(sb::associate(est, gt) == expected);
}

TEST_CASE("association rejects invalid options", "[eval][associate]") {
  const auto t = atTimes({0.0, 0.1});
  sb::AssociationOptions o;
  o.maxTimeDifference = -1.0;
  CHECK_THROWS_AS(sb::associate(t, t, o), sb::Error);
  o.maxTimeDifference = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(sb::associate(t, t, o), sb::Error);
}
