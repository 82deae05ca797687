// adaptive with the robot's odometry (docs/odometry.md): the level's ceiling, the tracking rate, iterations and
// reference size it runs at, on hand-made observations.

#include "tests/controller/adaptive_driver.h"

using namespace sb::test::adaptive;

TEST_CASE("adaptive with the robot's odometry relaxes no coarser than max_level_with_odometry",
          "[controller][adaptive]") {
  CHECK(config().maxLevelWithOdometry == 0);  // the default: a robot's frames at the finest compute size
  AdaptiveController c("adaptive", config(R"({"bootstrap_frames": 0, "relax_frames": 1,
                                              "max_level_with_odometry": 1})"));
  Driver drive(c);
  drive.odometry = true;
  for (int i = 0; i < 12; ++i) drive.step(moveX(0.01));
  CHECK(c.level() == 1);
  CHECK(drive.knobs.csr == 2);
  // The wheels gone (a handheld stretch, an odometry outage): the whole ladder again.
  drive.odometry = false;
  for (int i = 0; i < 6; ++i) drive.step(moveX(0.01));
  CHECK(c.level() == 3);
  // The wheels back: down to the ceiling at once, with the reason in the decision.
  drive.odometry = true;
  const Decision d = drive.step(moveX(0.01));
  CHECK(d.level == 1);
  CHECK_THAT(d.reason, Catch::Contains("max_level_with_odometry"));
  // Configurable: 3 lets the robot use the whole ladder.
  AdaptiveController free("adaptive", config(R"({"bootstrap_frames": 0, "relax_frames": 1,
                                                 "max_level_with_odometry": 3})"));
  Driver freeDrive(free);
  freeDrive.odometry = true;
  freeDrive.reachCoarsest();
}

TEST_CASE("with the robot's odometry adaptive tracks every third frame with fewer iterations, maps at csr 2",
          "[controller][adaptive]") {
  AdaptiveController c("adaptive", config(R"({"bootstrap_frames": 0})"));
  Driver drive(c);
  drive.odometry = true;
  Decision d;
  for (int i = 0; i < 8; ++i) d = drive.step(moveX(0.035));
  CHECK(d.next.csr == 1);
  CHECK(d.next.trackingRate == 3);
  CHECK(d.next.pyramidIterations == std::array<int, 3>{5, 3, 2});
  REQUIRE(d.referenceCsr);
  CHECK(*d.referenceCsr == 2);
  // A doubt (the tracked motion 0.065 m off the prediction): every frame tracked with the ladder's iterations for
  // hold_frames (15), then the wheels carry the skipped frames again.
  d = drive.step(moveX(0.1));
  CHECK((d.triggers & sb::kTriggerDoubt) == 0);  // no finer level to re-track at: the doubt holds the knobs
  CHECK(d.next.trackingRate == 1);
  CHECK(d.next.pyramidIterations == std::array<int, 3>{10, 5, 4});
  for (int i = 0; i < 14; ++i) d = drive.step(moveX(0.035));
  CHECK(d.next.trackingRate == 1);
  for (int i = 0; i < 2; ++i) d = drive.step(moveX(0.035));
  CHECK(d.next.trackingRate == 3);
  // Without the wheels: the ladder's knobs, the maps at the frame's compute size.
  drive.odometry = false;
  d = drive.step(moveX(0.035));
  CHECK(d.next == sb::KnobLadder().coupled(c.level()));
  CHECK_FALSE(d.referenceCsr);
  // Configurable, and checked by key.
  const sb::AdaptiveConfig every = config(R"({"tracking_rate_with_odometry": 1, "icp_iterations_with_odometry": [10, 5, 4],
                                              "reference_csr_with_odometry": 0})");
  CHECK(every.trackingRateWithOdometry == 1);
  CHECK(every.referenceCsrWithOdometry == 0);
  CHECK_THROWS_WITH(config(R"({"tracking_rate_with_odometry": 0})"), Catch::Contains("tracking_rate_with_odometry"));
  CHECK_THROWS_WITH(config(R"({"icp_iterations_with_odometry": [0, 3, 2]})"),
                    Catch::Contains("icp_iterations_with_odometry"));
  CHECK_THROWS_WITH(config(R"({"icp_iterations_with_odometry": [5, 3]})"), Catch::Contains("icp_iterations_with_odometry"));
  CHECK_THROWS_WITH(config(R"({"reference_csr_with_odometry": 3})"), Catch::Contains("reference_csr_with_odometry"));
}

TEST_CASE("frames skipped by the tracking rate count towards the integration's max gap", "[controller][adaptive]") {
  // A robot creeping (nothing new by distance): fused at least every integrate_max_gap_frames (4) frames, skipped
  // ones included. Before, only tracked frames counted: with tr 3 a fusion every 12 frames.
  AdaptiveController c("adaptive", config(R"({"bootstrap_frames": 0, "integrate_max_gap_frames": 4,
                                              "integrate_translation_m_with_odometry": 10})"));
  Driver drive(c);
  drive.odometry = true;
  for (int i = 0; i < 6; ++i) drive.step(moveX(0.0));  // the pipeline's bootstrap, then the first fusion
  std::vector<int> fusedAt;
  for (int frame = 0; frame < 18; ++frame) {
    Observation o = drive.observe(moveX(0.0));
    if (frame % 3 != 0) {  // skipped by tr 3: no tracking attempted
      o.trackingAttempted = o.tracked = false;
      o.pose = o.previousPose;
    }
    const Decision d = c.decide(o);
    drive.finish(o, d);
    if (d.integrate && *d.integrate) fusedAt.push_back(frame);
  }
  REQUIRE(fusedAt.size() == 3);  // every second tracked frame: 6 frames apart, the gap of 4 passed
  CHECK(fusedAt[1] - fusedAt[0] == 6);
  CHECK(fusedAt[2] - fusedAt[1] == 6);
}
