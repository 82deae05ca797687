// What a run keeps of the base in a map store, and writes of the store, end to end (issue 55): the runs of
// tests/tools/map_store_runs.h (the corridor drive's first run, frames 0-329, with a new store; restarts given a
// copy of it).
//
// The mount's correction kept (odometry.bin) is restored only for the mount it was learnt against: the store
// records the mount the odometry assumed (its up axis in the camera frame, runtime/kept_odometry.h). A restart
// whose odometry assumes the same mount starts from the kept correction (summary.json odometry.start_mount_error_deg;
// on this drive run 1 learnt none, 0.0 deg: what is tested is the decision, the restore itself is
// tests/runtime/test_map_store_state.cpp's); one whose odometry assumes a mount pitched 3 degrees further (`synth
// --odom-mount-error 0,3,0`: a mount re-measured) starts fresh, said in the log and in
// odometry.start_mount_refused, with the change measured (start_mount_change_deg).
#include <catch2/catch.hpp>
#include <string>

#include "tests/tools/map_store_runs.h"

using namespace sb::test::map_store;

TEST_CASE("a kept mount correction is restored for the mount it was learnt against, and not for another",
          "[tools][map_store][system]") {
  const std::string dir = sb::test::scratchDir("map_store_cli_mount");
  synth(" --frames-from 200 --frames-to 260 --out " + dir + "/same");
  synth(" --frames-from 200 --frames-to 260 --odom-mount-error 0,3,0 --out " + dir + "/moved");
  copyFirstStore(dir + "/store-same");
  copyFirstStore(dir + "/store-moved");

  std::string log;
  const nlohmann::json same = run(dir + "/same", dir + "/store-same", dir + "/out-same", "", &log)["odometry"];
  INFO("the same mount: " << same.dump());
  REQUIRE(same.contains("start_mount_change_deg"));
  CHECK(same["start_mount_change_deg"].get<double>() < 0.1);
  CHECK(same.contains("start_mount_error_deg"));
  CHECK_FALSE(same.contains("start_mount_refused"));
  CHECK(log.find("is not restored") == std::string::npos);

  const nlohmann::json moved = run(dir + "/moved", dir + "/store-moved", dir + "/out-moved", "", &log)["odometry"];
  INFO("a mount 3 degrees off: " << moved.dump() << "\n" << log);
  REQUIRE(moved.contains("start_mount_change_deg"));
  CHECK(moved["start_mount_change_deg"].get<double>() == Approx(3.0).margin(0.2));
  CHECK_FALSE(moved.contains("start_mount_error_deg"));
  REQUIRE(moved.contains("start_mount_refused"));
  CHECK(moved["start_mount_refused"].get<std::string>().find("the odometry's mount differs by 3.") != std::string::npos);
  CHECK(log.find("map store: the mount's correction kept in '" + dir + "/store-moved/odometry.bin'") !=
        std::string::npos);
  CHECK(log.find("start_mount_refused") != std::string::npos);
  // The wheels' calibration is the base's whatever the mount: both restarts start from it.
  CHECK(moved.value("calibration_from", std::string()) == dir + "/store-moved/odometry.bin");
}
