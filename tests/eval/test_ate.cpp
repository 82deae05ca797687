// computeAte(): known-answer cases for the Horn alignment, the error statistics, the paper's unaligned
// measure, and the degenerate inputs.

#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "core/error.h"
#include "eval/trajectory_eval.h"
#include "tests/eval/eval_test_util.h"

using Catch::Matchers::Contains;
using sb::test::makePose;

namespace {

Eigen::Isometry3d knownTransform() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(2.1, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(1.5, -2.0, 0.75);
  return T;
}

// Corners of cubes of half-size 1, 2, 3 (m) around `centre`; corner c of cube k is displaced by
// magnitude[k] * sign(x y z) along `dir`. The displacements have zero mean and no correlation with the
// positions, so the optimal alignment is the identity and every per-frame error equals its magnitude.
void cubePattern(const std::vector<double>& magnitudes, const Eigen::Vector3d& centre,
                 const Eigen::Vector3d& dir, sb::Trajectory* gt, sb::Trajectory* est) {
  double t = 0.0;
  for (size_t k = 0; k < magnitudes.size(); ++k) {
    const double h = static_cast<double>(k + 1);
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d s((c & 1) ? 1 : -1, (c & 2) ? 1 : -1, (c & 4) ? 1 : -1);
      const Eigen::Vector3d p = centre + h * s;
      gt->push_back(makePose(t, p));
      est->push_back(makePose(t, p + magnitudes[k] * s.prod() * dir.normalized()));
      t += 0.1;
    }
  }
}

}  // namespace

TEST_CASE("ATE of a trajectory under a known rigid transform is zero and the transform is recovered",
          "[eval][ate]") {
  const auto gt = sb::test::helixTrajectory(200);
  const Eigen::Isometry3d T = knownTransform();
  const auto est = sb::test::transformed(gt, T);
  const auto r = sb::computeAte(est, gt);
  CHECK(r.matches == gt.size());
  CHECK(r.rmse < 1e-9);
  CHECK(r.max < 1e-9);
  CHECK(r.unalignedMean < 1e-9);  // a change of world frame does not change relative poses
  CHECK((r.alignment.matrix() - T.inverse().matrix()).cwiseAbs().maxCoeff() < 1e-9);
  // The quaternion oracle agrees on this case too.
  Eigen::Isometry3d horn;
  CHECK(sb::test::hornQuaternionRmse(est, gt, &horn) < 1e-9);
  CHECK((horn.matrix() - T.inverse().matrix()).cwiseAbs().maxCoeff() < 1e-9);
}

TEST_CASE("ATE statistics of a zero-mean uncorrelated perturbation equal its known magnitudes",
          "[eval][ate]") {
  const std::vector<double> magnitudes = {0.01, 0.02, 0.06};  // m
  sb::Trajectory gt, est;
  cubePattern(magnitudes, Eigen::Vector3d(0.5, -1.0, 2.0), Eigen::Vector3d(1, 2, -1), &gt, &est);
  const double rmse = std::sqrt((0.01 * 0.01 + 0.02 * 0.02 + 0.06 * 0.06) / 3.0);

  SECTION("directly") {
    const auto r = sb::computeAte(est, gt);
    CHECK(r.matches == 24);
    CHECK(r.rmse == Approx(rmse).margin(1e-12));
    CHECK(r.mean == Approx(0.03).margin(1e-12));
    CHECK(r.median == Approx(0.02).margin(1e-12));
    CHECK(r.max == Approx(0.06).margin(1e-12));
    CHECK((r.alignment.matrix() - Eigen::Matrix4d::Identity()).cwiseAbs().maxCoeff() < 1e-12);
    for (size_t i = 0; i < r.errors.size(); ++i)
      CHECK(r.errors[i] == Approx(magnitudes[i / 8]).margin(1e-12));
  }
  SECTION("with the estimate in another world frame") {
    const Eigen::Isometry3d T = knownTransform();
    const auto r = sb::computeAte(sb::test::transformed(est, T), gt);
    CHECK(r.rmse == Approx(rmse).margin(1e-12));
    CHECK(r.median == Approx(0.02).margin(1e-12));
    CHECK((r.alignment.matrix() - T.inverse().matrix()).cwiseAbs().maxCoeff() < 1e-9);
  }
}

TEST_CASE("the unaligned error compares poses relative to the first matched pose", "[eval][ate]") {
  // Identity rotations; estimate = gt + d_i with d_0 = 0, so the relative translations differ by d_i.
  const std::vector<Eigen::Vector3d> gtPos = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 1}};
  const std::vector<Eigen::Vector3d> d = {{0, 0, 0}, {0.03, 0, 0}, {0, -0.04, 0}, {0.03, 0.04, 0}};
  sb::Trajectory gt, est;
  for (size_t i = 0; i < gtPos.size(); ++i) {
    gt.push_back(makePose(0.1 * static_cast<double>(i), gtPos[i]));
    est.push_back(makePose(0.1 * static_cast<double>(i), gtPos[i] + d[i]));
  }
  // A world-frame change of the estimate (left multiplication) must not change the measure.
  const auto r = sb::computeAte(sb::test::transformed(est, knownTransform()), gt);
  REQUIRE(r.unalignedErrors.size() == 4);
  CHECK(r.unalignedErrors[0] == Approx(0.0).margin(1e-12));
  CHECK(r.unalignedErrors[1] == Approx(0.03).margin(1e-12));
  CHECK(r.unalignedErrors[2] == Approx(0.04).margin(1e-12));
  CHECK(r.unalignedErrors[3] == Approx(0.05).margin(1e-12));
  CHECK(r.unalignedMean == Approx(0.03).margin(1e-12));

  SECTION("the first pose's rotation re-expresses the offsets in its frame") {
    // Rotating every gt pose's orientation by the same camera-side rotation leaves the first-relative
    // translations of gt rotated by R0^T; the estimate keeps identity orientations, so errors change.
    sb::Trajectory rotated = gt;
    for (auto& p : rotated)
      p.T_camera_to_world.linear() = Eigen::AngleAxisd(EIGEN_PI / 2, Eigen::Vector3d::UnitZ()).matrix();
    const auto r2 = sb::computeAte(gt, rotated);
    // gt relative translation of pose 1 in the rotated frame: R^T (1,0,0) = (0,-1,0); estimate: (1,0,0).
    CHECK(r2.unalignedErrors[1] == Approx(std::sqrt(2.0)).margin(1e-12));
  }
}

TEST_CASE("ATE reports each degenerate input as an error", "[eval][ate][errors]") {
  SECTION("fewer than 3 matches") {
    sb::Trajectory t = {makePose(0.0, {0, 0, 0}), makePose(0.1, {1, 0, 0})};
    CHECK_THROWS_WITH(sb::computeAte(t, t), Contains("only 2 poses associate"));
  }
  SECTION("no overlap in time names both time ranges") {
    const auto gt = sb::test::helixTrajectory(31);  // 0 .. 1 s
    sb::Trajectory est = gt;
    for (auto& p : est) p.timestamp += 10.0;
    CHECK_THROWS_WITH(sb::computeAte(est, gt), Contains("no overlap in time") &&
                                                   Contains("10.000000 .. 11.000000") &&
                                                   Contains("0.000000 .. 1.000000"));
  }
  SECTION("empty trajectories") {
    const auto gt = sb::test::helixTrajectory(10);
    CHECK_THROWS_WITH(sb::computeAte({}, gt), Contains("no poses"));
    CHECK_THROWS_WITH(sb::computeAte(gt, {}), Contains("no poses"));
  }
  SECTION("identical positions") {
    sb::Trajectory t;
    for (int i = 0; i < 10; ++i) t.push_back(makePose(0.1 * i, {1, 2, 3}, {0, 0, 1}, 0.1 * i));
    CHECK_THROWS_WITH(sb::computeAte(t, sb::test::helixTrajectory(10, 10.0)), Contains("identical"));
  }
  SECTION("collinear positions, in either trajectory") {
    sb::Trajectory line;
    for (int i = 0; i < 10; ++i) line.push_back(makePose(0.1 * i, Eigen::Vector3d(1, 2, 3) * (0.1 * i)));
    const auto helix = sb::test::helixTrajectory(10, 10.0);
    CHECK_THROWS_WITH(sb::computeAte(line, helix), Contains("collinear") && Contains("estimate"));
    CHECK_THROWS_WITH(sb::computeAte(helix, line), Contains("collinear") && Contains("ground truth"));
  }
  SECTION("planar sets whose variations do not correlate") {
    const std::vector<Eigen::Vector3d> e = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    const std::vector<Eigen::Vector3d> g = {{1, 1, 0}, {-1, 1, 0}, {0, -1, 0}, {0, -1, 0}};
    sb::Trajectory est, gt;
    for (size_t i = 0; i < e.size(); ++i) {
      est.push_back(makePose(0.1 * static_cast<double>(i), e[i]));
      gt.push_back(makePose(0.1 * static_cast<double>(i), g[i]));
    }
    CHECK_THROWS_WITH(sb::computeAte(est, gt), Contains("cross-covariance"));
  }
}

TEST_CASE("a planar trajectory aligns without reflection", "[eval][ate]") {
  // Points in the z = 0 plane: SVD alone could return a reflection (det -1); the result must be a rotation.
  sb::Trajectory gt;
  for (int i = 0; i < 12; ++i) gt.push_back(makePose(0.1 * i, {std::cos(0.5 * i), std::sin(0.5 * i), 0.0}));
  const Eigen::Isometry3d T = knownTransform();
  const auto r = sb::computeAte(sb::test::transformed(gt, T), gt);
  CHECK(r.alignment.linear().determinant() == Approx(1.0).margin(1e-12));
  CHECK(r.rmse < 1e-9);
  CHECK((r.alignment.matrix() - T.inverse().matrix()).cwiseAbs().maxCoeff() < 1e-9);
}

TEST_CASE("ATE with a fixed alignment maps the estimate by it instead of fitting one (a run in another's frame)",
          "[eval][ate]") {
  const auto gt = sb::test::helixTrajectory(200);
  const Eigen::Isometry3d T = knownTransform();
  const auto est = sb::test::transformed(gt, T);
  // The right frame: the errors vanish; a frame 0.3 m off along x: every frame 0.3 m off, nothing refitted.
  const Eigen::Isometry3d right = T.inverse();
  CHECK(sb::computeAte(est, gt, {}, &right).max < 1e-9);
  Eigen::Isometry3d off = right;
  off.translation() += Eigen::Vector3d(0.3, 0.0, 0.0);
  const auto r = sb::computeAte(est, gt, {}, &off);
  CHECK(r.rmse == Approx(0.3).margin(1e-9));
  CHECK(r.max == Approx(0.3).margin(1e-9));
  CHECK(r.alignment.isApprox(off, 0.0));
}

TEST_CASE("alignFrames recovers a known change of frame from whole poses", "[eval][ate]") {
  const auto gt = sb::test::helixTrajectory(200);
  const Eigen::Isometry3d T = knownTransform();
  CHECK(sb::alignFrames(sb::test::transformed(gt, T.inverse()), gt).isApprox(T, 1e-9));
}

TEST_CASE("a straight run's frame fitted on whole poses holds the rotation about its line (positions alone do not)",
          "[eval][ate]") {
  // Run 1 drives 9 m along z with a 2 cm sideways wiggle; its estimate has the orientations right but the wiggle
  // turned 60 degrees about the line (centimetres of noise). Its positions alone fit a frame turned about the
  // line; run 2, 0.8 m beside the line and exact, is then ~0.8 m off in that frame, and within millimetres in
  // the frame fitted on whole poses.
  sb::Trajectory gt1, est1, gt2, est2;
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(1.047, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (int i = 0; i < 300; ++i) {
    const double t = i / 30.0, s = (i % 2 == 0 ? 1.0 : -1.0) * 0.02;
    const Eigen::Vector3d line(0.4, 0.0, 0.03 * i), wiggle(s, 0.0, 0.0);
    gt1.push_back(makePose(t, line + wiggle));
    est1.push_back(makePose(t, line + turn * wiggle));
    gt2.push_back(makePose(t, Eigen::Vector3d(-0.4, 0.0, 0.03 * i)));
  }
  est2 = gt2;
  const Eigen::Isometry3d positionsOnly = sb::computeAte(est1, gt1).alignment;
  const Eigen::Isometry3d poses = sb::alignFrames(est1, gt1);
  CHECK(sb::computeAte(est2, gt2, {}, &positionsOnly).rmse > 0.3);
  CHECK(sb::computeAte(est2, gt2, {}, &poses).max < 0.005);
}
