// adaptive on hand-made observation sequences: each decision rule (relax, re-track, confirm, correction only
// on failure, integration gate, unconstrained frames) against exact expectations.

#include "core/error.h"
#include "tests/controller/adaptive_driver.h"

using namespace sb::test::adaptive;

TEST_CASE("adaptive relaxes one level per relax_frames after its bootstrap, up to max_level", "[controller][adaptive]") {
  AdaptiveController c("adaptive", config(R"({"bootstrap_frames": 6, "relax_frames": 2})"));
  Driver drive(c);
  std::vector<int> levels;
  for (int i = 0; i < 16; ++i) levels.push_back(drive.step(moveX(0.001)).level);
  // Observations 1-6 are the bootstrap; then one level per 2 undoubted frames, up to 3.
  CHECK(levels == std::vector<int>{0, 0, 0, 0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 3, 3, 3});
  CHECK(drive.knobs == sb::Knobs{8, 1e-4, {4, 5, 4}, 1, 1});
}

TEST_CASE("adaptive never corrects fast motion that ICP tracks consistently", "[controller][adaptive]") {
  AdaptiveController c("adaptive", config(R"({"bootstrap_frames": 0, "relax_frames": 1})"));
  Driver drive(c);
  // 0.06 m/frame (1.8 m/s) from the first tracked frame on, with a ramp-up the prediction follows.
  for (int i = 0; i < 40; ++i) {
    const double speed = i < 4 ? 0.0 : std::min(0.06, 0.01 * (i - 3));
    const Decision d = drive.step(moveX(speed));
    CHECK_FALSE(d.correctedPose);
    CHECK((d.triggers & sb::kTriggerCorrection) == 0);
  }
  CHECK(c.level() == 3);  // well-tracked fast motion runs at the coarsest level
}

TEST_CASE("adaptive re-tracks a doubtful coarse frame finer and corrects only when that fails too", "[controller][adaptive]") {
  AdaptiveController c("adaptive", config(R"({"bootstrap_frames": 0, "relax_frames": 1, "retrack_levels": 2,
      "hold_frames": 5})"));
  Driver drive(c);
  drive.reachCoarsest();
  // Tracking fails at csr=8: the frame is tracked again two levels finer.
  Observation first = drive.observe(moveX(0.01), false);
  Decision d = c.decide(first);
  REQUIRE(d.retrack);
  CHECK(d.retrack->csr == 2);
  CHECK_FALSE(d.correctedPose);
  // It fails there too: constant-velocity extrapolation, the level goes to the re-track's, no integration.
  Observation second = Driver::retrackOf(first, d);
  d = c.decide(second);
  CHECK_FALSE(d.retrack);
  REQUIRE(d.correctedPose);
  CHECK(d.correctedPose->translation().isApprox(first.previousPose.translation() + Eigen::Vector3d(0.01, 0, 0)));
  CHECK((d.triggers & sb::kTriggerCorrection) != 0);
  CHECK(d.level == 1);
  CHECK(d.next.csr == 2);
  REQUIRE(d.integrate);
  CHECK_FALSE(*d.integrate);
  CHECK(d.reason.find("track failed") != std::string::npos);
  drive.finish(second, d);
  // Held finer for hold_frames, then relaxing again.
  std::vector<int> levels;
  for (int i = 0; i < 9; ++i) levels.push_back(drive.step(moveX(0.01)).level);
  CHECK(levels == std::vector<int>{1, 1, 1, 1, 1, 2, 3, 3, 3});
}

TEST_CASE("adaptive keeps its level when the re-track confirms the coarse pose", "[controller][adaptive]") {
  AdaptiveController c("adaptive", config(R"({"bootstrap_frames": 0, "relax_frames": 1, "retrack_levels": 1})"));
  Driver drive(c);
  drive.reachCoarsest();
  // The tracked motion jumps to 0.05 m/frame, 0.04 m off the prediction: doubted, re-tracked at csr=4.
  Observation first = drive.observe(moveX(0.05));
  Decision d = c.decide(first);
  REQUIRE(d.retrack);
  CHECK(d.retrack->csr == 4);
  CHECK(d.reason.find("prediction off") != std::string::npos);
  // The finer pass lands 2 mm from the coarse pose: confirmed, the motion is real.
  Observation second = Driver::retrackOf(first, d);
  second.pose.translation().x() += 0.002;
  d = c.decide(second);
  CHECK_FALSE(d.correctedPose);
  CHECK(d.level == 3);
  CHECK(d.reason.find("confirmed") != std::string::npos);
  drive.finish(second, d);
  // A re-track 3 cm away from the coarse pose: the coarse level was wrong here, one level finer.
  first = drive.observe(moveX(0.10));
  d = c.decide(first);
  REQUIRE(d.retrack);
  second = Driver::retrackOf(first, d);
  second.pose.translation().x() -= 0.03;
  d = c.decide(second);
  CHECK_FALSE(d.correctedPose);
  CHECK(d.level == 2);
}

TEST_CASE("adaptive fuses a frame when it brings something new, at least every max gap", "[controller][adaptive]") {
  AdaptiveController c("adaptive", config(R"({"bootstrap_frames": 0, "retrack_levels": 0, "integrate_translation_m": 0.02,
      "integrate_translation_m_with_odometry": 0.1, "integrate_rotation_deg": 2, "integrate_max_gap_frames": 4})"));
  Driver drive(c);
  for (int i = 0; i < 4; ++i) drive.step(moveX(0.0));  // pipeline bootstrap: no override
  std::vector<int> fused;
  for (int i = 0; i < 9; ++i) {
    const Decision d = drive.step(moveX(0.0));
    REQUIRE(d.integrate);
    fused.push_back(*d.integrate);
    CHECK(d.keepReference == !*d.integrate);
  }
  CHECK(fused == std::vector<int>{1, 0, 0, 0, 1, 0, 0, 0, 1});  // still camera: every 4th frame
  fused.clear();
  for (int i = 0; i < 6; ++i) fused.push_back(*drive.step(moveX(0.011)).integrate);
  CHECK(fused == std::vector<int>{0, 1, 0, 1, 0, 1});  // 1.1 cm/frame: every second frame passes 2 cm
  fused.clear();
  for (int i = 0; i < 4; ++i) fused.push_back(*drive.step(moveX(0.03)).integrate);
  CHECK(fused == std::vector<int>{1, 1, 1, 1});  // fast: every frame
  Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();
  turn.linear() = Eigen::AngleAxisd(2.5 * 3.141592653589793 / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  CHECK(*drive.step(turn).integrate);  // 2.5 degrees
  // The robot's odometry drives the frames: fused every integrate_translation_m_with_odometry (0.1 m here).
  drive.odometry = true;
  fused.clear();
  for (int i = 0; i < 8; ++i) fused.push_back(*drive.step(moveX(0.035)).integrate);
  CHECK(fused == std::vector<int>{0, 0, 1, 0, 0, 1, 0, 0});  // 3.5 cm/frame: every third frame passes 10 cm
}

TEST_CASE("adaptive re-tracks an unconstrained view and goes finer only when that finds structure", "[controller][adaptive]") {
  AdaptiveController c("adaptive", config(R"({"bootstrap_frames": 0, "relax_frames": 1, "hold_frames": 0,
      "integrate_max_gap_frames": 1})"));
  Driver drive(c);
  drive.reachCoarsest();
  const auto wall = [&](bool secondConstrained) {
    Observation first = drive.observe(moveX(0.01));
    first.quality = {true, 0.0002, 0.0002, sb::WeakDirection::ty, false};
    Decision d = c.decide(first);
    REQUIRE(d.retrack);
    CHECK(d.reason == "retrack: weakly constrained (ICP conditioning 0.0002, ty)");
    Observation second = Driver::retrackOf(first, d);
    if (secondConstrained) second.quality = {true, 0.1, 0.1, sb::WeakDirection::tx, true};
    d = c.decide(second);
    CHECK_FALSE(d.correctedPose);  // nothing says ICP is wrong along the motions the view does fix
    REQUIRE(d.integrate);
    CHECK(*d.integrate);  // off only along motions that leave the view unchanged: fused
    return drive.finish(second, d);
  };
  // A blank wall at both levels: the finer level adds nothing, the level stays.
  Decision d = wall(false);
  CHECK((d.triggers & sb::kTriggerUnconstrained) != 0);
  CHECK(d.level == 3);
  // Constrained at the finer level: the coarse images lost structure here, one level finer.
  d = wall(true);
  CHECK((d.triggers & sb::kTriggerUnconstrained) == 0);
  CHECK(d.level == 2);
  // The doubt reads the per-pixel ICP conditioning (its threshold was set on it), not the structure's: a view
  // whose structure is flagged but whose ICP problem is well conditioned is not re-tracked.
  Observation flagged = drive.observe(moveX(0.01));
  flagged.quality = {true, 0.0001, 0.1, sb::WeakDirection::tx, false};
  CHECK_FALSE(c.decide(flagged).retrack);
}

TEST_CASE("adaptive holds the pose once a failure lasts longer than the extrapolation limit", "[controller][adaptive]") {
  AdaptiveController c("adaptive", config(R"({"bootstrap_frames": 0, "retrack_levels": 0,
      "correction_max_extrapolated_frames": 2})"));
  Driver drive(c);
  for (int i = 0; i < 8; ++i) drive.step(moveX(0.01));
  CHECK(drive.step(moveX(0.01), false).correctedPose);
  CHECK(drive.step(moveX(0.01), false).correctedPose);
  CHECK_FALSE(drive.step(moveX(0.01), false).correctedPose);
}

TEST_CASE("adaptive's settings are checked by key", "[controller][adaptive]") {
  CHECK_THROWS_WITH(config(R"({"integrate_max_gap_frames": 0})"), Catch::Contains("integrate_max_gap_frames"));
  CHECK_THROWS_WITH(config(R"({"doubt_prediction_rotation_deg": -1})"), Catch::Contains("doubt_prediction_rotation_deg"));
  CHECK_THROWS_WITH(config(R"({"retrack": 1})"), Catch::Contains("retrack"));
}

TEST_CASE("adaptive starts the next frame's ICP from the constant-velocity prediction", "[controller][adaptive]") {
  AdaptiveController c("adaptive", config(R"({"bootstrap_frames": 0})"));
  Driver drive(c);
  for (int i = 0; i < 4; ++i) CHECK_FALSE(drive.step(moveX(0.0)).nextStartPose);  // no motion learnt yet
  drive.step(moveX(0.05));
  const Observation o = drive.observe(moveX(0.05));
  const Decision d = c.decide(o);
  REQUIRE(d.nextStartPose);
  CHECK(d.nextStartPose->translation().isApprox(o.pose.translation() + Eigen::Vector3d(0.05, 0, 0)));
  AdaptiveController off("adaptive", config(R"({"bootstrap_frames": 0, "predict_start": false})"));
  Driver other(off);
  for (int i = 0; i < 8; ++i) CHECK_FALSE(other.step(moveX(0.05)).nextStartPose);
}

TEST_CASE("adaptive does not learn a motion that ICP left unconverged or off the prediction (no runaway prior)",
          "[controller][adaptive]") {
  // At the finest level (no re-track possible) the tracked motion slides ahead of the prediction by 0.1 m per
  // frame: what ICP does along a corridor's axis. Learnt, each start pose would carry the last slide on.
  AdaptiveController c("adaptive", config(R"({"bootstrap_frames": 0, "max_level": 0})"));
  Driver drive(c);
  for (int i = 0; i < 4; ++i) drive.step(moveX(0.0));
  drive.step(moveX(0.05));  // first tracked motion: learnt, nothing to check it against
  const Decision slid = drive.step(moveX(0.15));  // 0.10 m off the prediction: not learnt
  CHECK_FALSE(slid.nextStartPose);  // the next frame starts from this pose, as DEFAULT does
  drive.step(moveX(0.02));          // learnt again from a plausible motion (no prediction to doubt it)
  const Observation o = drive.observe(moveX(0.02));
  const Decision d = c.decide(o);
  REQUIRE(d.nextStartPose);
  CHECK(d.nextStartPose->translation().isApprox(o.pose.translation() + Eigen::Vector3d(0.02, 0, 0)));
  // ICP still moving after every iteration at the finest level: not a measured motion either.
  Observation moving = drive.observe(moveX(0.02));
  moving.icpLevelIterations = {moving.knobs.pyramidIterations[0], 1, 1};
  moving.icpUpdateNorm = 0.02;
  CHECK_FALSE(c.decide(moving).nextStartPose);
}

TEST_CASE("adaptive fuses an unconverged frame at the finest level, where no re-track can settle it",
          "[controller][adaptive]") {
  // At the finest level a frame that ICP left still moving cannot be re-tracked finer. Left unfused, the map
  // stops following the camera and the next frames lose it (a sparse corridor seen lengthwise: lost from
  // frame 204 of 300 while DEFAULT, which fuses such frames, tracked them all). Fused, it is what DEFAULT does;
  // its motion is still not learnt (no runaway prior). A coarser level re-tracks instead.
  const char* cfg = R"({"bootstrap_frames": 0, "max_level": 0, "integrate_translation_m": 0,
      "integrate_rotation_deg": 0, "integrate_max_gap_frames": 1})";
  AdaptiveController c("adaptive", config(cfg));
  Driver drive(c);
  for (int i = 0; i < 4; ++i) drive.step(moveX(0.0));
  Observation moving = drive.observe(moveX(0.03));
  moving.icpLevelIterations = {moving.knobs.pyramidIterations[0], 1, 1};
  moving.icpUpdateNorm = 0.02;
  const Decision d = c.decide(moving);
  REQUIRE_FALSE(d.retrack);
  REQUIRE(d.integrate);
  CHECK(*d.integrate);
  CHECK_FALSE(d.nextStartPose);
  // The same frame at a coarser level is re-tracked finer, not fused as it is.
  AdaptiveController coarse("adaptive", config(R"({"bootstrap_frames": 0, "relax_frames": 1})"));
  Driver other(coarse);
  other.reachCoarsest();
  Observation unsettled = other.observe(moveX(0.03));
  unsettled.icpLevelIterations = {unsettled.knobs.pyramidIterations[0], 1, 1};
  unsettled.icpUpdateNorm = 0.02;
  const Decision again = coarse.decide(unsettled);
  CHECK(again.retrack);
  CHECK(again.reason.find("not converged") != std::string::npos);
}

TEST_CASE("adaptive asks ICP to hold free motions only when configured", "[controller][adaptive]") {
  AdaptiveController off("adaptive", config(R"({"bootstrap_frames": 0})"));
  Driver drive(off);
  CHECK(drive.step(moveX(0.0)).nextHoldBelowConditioning == 0.0);
  AdaptiveController on("adaptive", config(R"({"bootstrap_frames": 0, "relax_frames": 1000, "icp_hold_conditioning": 0.0006})"));
  Driver other(on);
  for (int i = 0; i < 6; ++i) CHECK(other.step(moveX(0.01)).nextHoldBelowConditioning == 0.0006);
  // A weak view does not stop the motion model: the next start is still the prediction.
  Observation wall = other.observe(moveX(0.01));
  wall.quality = {true, 0.0001, 0.0001, sb::WeakDirection::tx, false};
  const Decision d = other.finish(wall, on.decide(wall));
  CHECK(d.nextHoldBelowConditioning == 0.0006);
  CHECK(d.nextStartPose);
  CHECK((d.triggers & sb::kTriggerUnconstrained) != 0);
}

TEST_CASE("adaptive replaces a re-tracked pose that confirms nothing by the prediction, and does not learn it",
          "[controller][adaptive]") {
  // The 5 m-volume drive: an unconverged csr 8 pass, then a csr 4 pass with half the inliers 0.14 m ahead of
  // both the prediction and the first pass. Learnt, it lost the next frames.
  AdaptiveController c("adaptive", config(R"({"bootstrap_frames": 0, "relax_frames": 1})"));
  Driver drive(c);
  drive.reachCoarsest();
  Observation first = drive.observe(moveX(0.01));
  first.icpLevelIterations = {first.knobs.pyramidIterations[0], 1, 1};
  first.icpUpdateNorm = 0.02;
  Decision d = c.decide(first);
  REQUIRE(d.retrack);
  Observation second = Driver::retrackOf(first, d);
  second.icpUpdateNorm = 0.001;
  second.pose = moveX(0.15) * first.previousPose;
  second.inlierFraction = 0.2;  // below half the recent median (0.6)
  d = c.decide(second);
  const Eigen::Vector3d predicted = first.previousPose.translation() + Eigen::Vector3d(0.01, 0, 0);
  REQUIRE(d.correctedPose);
  CHECK(d.correctedPose->translation().isApprox(predicted));
  CHECK((d.triggers & sb::kTriggerCorrection) != 0);
  REQUIRE(d.integrate);
  CHECK_FALSE(*d.integrate);
  REQUIRE(d.nextStartPose);  // the motion model still holds the 0.01 m/frame it had
  CHECK(d.nextStartPose->translation().isApprox(predicted + Eigen::Vector3d(0.01, 0, 0)));
  drive.finish(second, d);

  // A re-track that lands on the first pass confirms it, even off the prediction: a real change of motion.
  AdaptiveController other("adaptive", config(R"({"bootstrap_frames": 0, "relax_frames": 1})"));
  Driver again(other);
  again.reachCoarsest();
  Observation fast = again.observe(moveX(0.06));
  d = other.decide(fast);
  REQUIRE(d.retrack);
  Observation agreeing = Driver::retrackOf(fast, d);
  d = other.decide(agreeing);
  CHECK_FALSE(d.correctedPose);
  REQUIRE(d.nextStartPose);
  CHECK(d.nextStartPose->translation().isApprox(fast.pose.translation() + Eigen::Vector3d(0.06, 0, 0)));
}

// Six frames at 0.01 m/frame along x, then one that ICP moved 0.012 along x and slid 0.02 along y, in a view
// (walls, no floor) whose structure fixes x and the rotations but leaves y free.
Observation slideAlongFreeY(Driver& drive) {
  for (int i = 0; i < 6; ++i) drive.step(moveX(0.01));
  Observation walls = drive.observe(Eigen::Isometry3d(Eigen::Translation3d(0.012, 0.02, 0.0)));
  sb::TrackingQuality q{true, 1e-7, 0.01, sb::WeakDirection::ty, false};
  q.structure = sb::Matrix6::Identity() * 0.05;
  q.structure(1, 1) = 1e-7;
  walls.quality = q;
  return walls;
}

TEST_CASE("adaptive learns a motion only as far as the view fixes it (learn_conditioning)", "[controller][adaptive]") {
  // The view fixes x and the rotations but leaves y free (walls only, no floor): ICP's 0.02 m slide along y
  // is not learnt; its x motion is.
  const char* cfg = R"({"bootstrap_frames": 0, "max_level": 0, "learn_conditioning": 0.001})";
  AdaptiveController c("adaptive", config(cfg));
  Driver drive(c);
  const Observation walls = slideAlongFreeY(drive);
  const Decision d = c.decide(walls);
  REQUIRE(d.nextStartPose);
  const Eigen::Vector3d step = d.nextStartPose->translation() - walls.pose.translation();
  CHECK(step.x() == Approx(0.01 + 0.002 * 0.05 / 0.051).margin(1e-6));
  CHECK(step.y() == Approx(0.0).margin(1e-5));
  // Off (0), the whole measured motion is learnt.
  AdaptiveController off("adaptive", config(R"({"bootstrap_frames": 0, "max_level": 0, "learn_conditioning": 0})"));
  Driver other(off);
  const Observation same = slideAlongFreeY(other);
  const Decision all = off.decide(same);
  REQUIRE(all.nextStartPose);
  CHECK((all.nextStartPose->translation() - same.pose.translation()).isApprox(Eigen::Vector3d(0.012, 0.02, 0)));
}

