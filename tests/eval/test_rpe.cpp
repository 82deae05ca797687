// computeRpe(): exact copies give zero, a known constant drift gives its known value, frames and seconds.

#include <catch2/catch.hpp>
#include <cmath>

#include "core/error.h"
#include "eval/trajectory_eval.h"
#include "tests/eval/eval_test_util.h"

using Catch::Matchers::Contains;

namespace {

// Estimate = ground truth with the position drifting by `drift` (world frame, m) per frame.
sb::Trajectory withTranslationDrift(const sb::Trajectory& gt, const Eigen::Vector3d& drift) {
  sb::Trajectory est = gt;
  for (size_t i = 0; i < est.size(); ++i)
    est[i].T_camera_to_world.translation() += static_cast<double>(i) * drift;
  return est;
}

}  // namespace

TEST_CASE("RPE of an exact copy is zero", "[eval][rpe]") {
  const auto gt = sb::test::helixTrajectory(100);
  const auto r = sb::computeRpe(gt, gt, 1, false);
  CHECK(r.pairs == 99);
  CHECK(r.translationRmse < 1e-12);
  CHECK(r.rotationRmse < 1e-6);  // degrees; acos-free angle extraction keeps this tight
  const auto s = sb::computeRpe(gt, gt, 1.0, true);
  CHECK(s.pairs == 70);  // 30 Hz: frames 0..69 have a partner 30 frames later
  CHECK(s.translationMean < 1e-12);
}

TEST_CASE("RPE of a constant translation drift is the drift times the delta", "[eval][rpe]") {
  const auto gt = sb::test::helixTrajectory(100);
  const Eigen::Vector3d drift(0.003, -0.004, 0.0);  // 5 mm per frame
  const auto est = withTranslationDrift(gt, drift);
  SECTION("per frame") {
    const auto r = sb::computeRpe(est, gt, 1, false);
    CHECK(r.pairs == 99);
    CHECK(r.translationRmse == Approx(0.005).margin(1e-12));
    CHECK(r.translationMean == Approx(0.005).margin(1e-12));
    CHECK(r.rotationMean < 1e-6);
  }
  SECTION("over 4 frames") {
    const auto r = sb::computeRpe(est, gt, 4, false);
    CHECK(r.pairs == 96);
    CHECK(r.translationMean == Approx(0.020).margin(1e-12));
  }
  SECTION("per second at 30 Hz") {
    const auto r = sb::computeRpe(est, gt, 1.0, true);
    CHECK(r.pairs == 70);
    CHECK(r.translationRmse == Approx(0.150).margin(1e-12));
  }
}

TEST_CASE("RPE of a constant rotation drift is the drift angle times the delta", "[eval][rpe]") {
  // Ground truth translates only (identity orientation); the estimate turns 0.5 degree per frame.
  constexpr double kDegPerFrame = 0.5;
  sb::Trajectory gt, est;
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector3d p(0.01 * i, 0.02 * std::sin(0.1 * i), 0.0);
    gt.push_back(sb::test::makePose(i / 30.0, p));
    est.push_back(
        sb::test::makePose(i / 30.0, p, Eigen::Vector3d::UnitZ(), kDegPerFrame * i * EIGEN_PI / 180.0));
  }
  const auto r = sb::computeRpe(est, gt, 3, false);
  CHECK(r.pairs == 47);
  CHECK(r.rotationMean == Approx(1.5).margin(1e-9));
  CHECK(r.rotationRmse == Approx(1.5).margin(1e-9));
}

TEST_CASE("RPE rejects bad deltas and too short trajectories", "[eval][rpe][errors]") {
  const auto gt = sb::test::helixTrajectory(10);
  CHECK_THROWS_WITH(sb::computeRpe(gt, gt, 0, false), Contains("positive"));
  CHECK_THROWS_WITH(sb::computeRpe(gt, gt, 1.5, false), Contains("whole number"));
  CHECK_THROWS_WITH(sb::computeRpe(gt, gt, 10, false), Contains("no matched poses are 10 frames apart"));
  CHECK_THROWS_WITH(sb::computeRpe(gt, gt, 2.0, true), Contains("use a smaller delta"));
  sb::Trajectory one = {gt.front()};
  CHECK_THROWS_WITH(sb::computeRpe(one, gt, 1, false), Contains("only 1 poses associate"));
}
