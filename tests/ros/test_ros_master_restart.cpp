// A ROS master killed and started again (issue 44 B3c), with a real master (Debian's rosmaster): the bridge
// says so and exits with status 3 for its supervisor to start it again (ros/master_watch.h); while the
// master is down it waits. This test program is no ROS node itself (roscpp allows one master per process).

#include <catch2/catch.hpp>
#include <memory>
#include <string>

#include "ros/master_watch.h"
#include "tests/ros/ros_fixture.h"
#include "tests/support/test_data.h"

using namespace sb::test;
using namespace sb::test::ros_e2e;

TEST_CASE("a restarted ROS master: the bridge says so and exits for its supervisor", "[ros][system]") {
  const std::string dir = scratchDir("ros_master_restart");
  const int port = freePort();
  auto master = std::make_unique<RosMaster>(dir, port);
  // No daemon: the bridge registers with the master, then retries the daemon's socket.
  auto bridge = startBridge(*master, {"socket:=" + dir + "/no-daemon.sock", "reconnect_s:=0.2"}, dir + "/bridge.log");
  REQUIRE(waitFor([&] { return bridge->log().find("retrying") != std::string::npos; }, 30.0));
  master.reset();  // SIGINT, waited for
  REQUIRE(waitFor([&] { return bridge->log().find("does not answer") != std::string::npos; }, 10.0));
  master = std::make_unique<RosMaster>(dir, port);
  const int status = bridge->wait(30.0);
  INFO(bridge->log());
  CHECK(status == sb::ros_bridge::kMasterRestartedExit);
  CHECK(bridge->log().find("was restarted") != std::string::npos);
}
