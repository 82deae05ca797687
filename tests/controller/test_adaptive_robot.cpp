// adaptive with the robot's odometry (docs/odometry.md): the level's ceiling on hand-made observations.

#include "tests/controller/adaptive_driver.h"

using namespace sb::test::adaptive;

TEST_CASE("adaptive with the robot's odometry relaxes no coarser than max_level_with_odometry",
          "[controller][adaptive]") {
  AdaptiveController c("adaptive", config(R"({"bootstrap_frames": 0, "relax_frames": 1})"));
  Driver drive(c);
  drive.odometry = true;
  for (int i = 0; i < 12; ++i) drive.step(moveX(0.01));
  CHECK(c.level() == 1);  // the default ceiling: csr 2
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
