// [data] ATE on the real 7-Scenes redkitchen ground truth (../shared/data).

#include <catch2/catch.hpp>

#include "core/trajectory.h"
#include "eval/trajectory_eval.h"
#include "tests/eval/eval_test_util.h"
#include "tests/support/test_data.h"

namespace {

sb::Trajectory redkitchenGroundTruth() {
  return sb::readTumTrajectory(sb::test::sharedDataDir() + "/7scenes-redkitchen-a/groundtruth.txt");
}

}  // namespace

TEST_CASE("7-Scenes ground truth against itself under a known rigid transform has zero ATE", "[eval][data]") {
  const auto gt = redkitchenGroundTruth();
  REQUIRE(gt.size() > 100);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(-0.7, Eigen::Vector3d(1, 0.2, -0.4).normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(-3.0, 0.5, 12.0);
  const auto r = sb::computeAte(sb::test::transformed(gt, T), gt);
  CHECK(r.matches == gt.size());
  CHECK(r.rmse < 1e-9);
  CHECK(r.unalignedMean < 1e-9);
  CHECK((r.alignment.matrix() - T.inverse().matrix()).cwiseAbs().maxCoeff() < 1e-9);
}

TEST_CASE("7-Scenes ground truth shifted by one frame matches an independent Horn alignment",
          "[eval][data]") {
  const auto gt = redkitchenGroundTruth();
  REQUIRE(gt.size() > 100);
  // Estimate pose i = ground-truth pose i+1 stamped with the time of pose i.
  sb::Trajectory est;
  for (size_t i = 0; i + 1 < gt.size(); ++i) {
    sb::TimedPose p = gt[i + 1];
    p.timestamp = gt[i].timestamp;
    est.push_back(p);
  }
  const auto r = sb::computeAte(est, gt);
  REQUIRE(r.matches == est.size());
  const sb::Trajectory gtMatched(gt.begin(), gt.end() - 1);
  Eigen::Isometry3d horn;
  const double oracle = sb::test::hornQuaternionRmse(est, gtMatched, &horn);
  CHECK(r.rmse > 1e-4);  // the camera moves between frames
  CHECK(r.rmse == Approx(oracle).margin(1e-9));
  CHECK((r.alignment.matrix() - horn.matrix()).cwiseAbs().maxCoeff() < 1e-6);
  CHECK(r.unalignedMean > 0.0);
}
