// ~map end to end against a real ROS master (issue 45): the daemon replays the short synthetic sequence with a
// navigation map (a camera mount says which way is up), writes its grid every 0.5 s and answers ?MAP; the
// bridge publishes it latched on ~map; this program subscribes and checks the grid it gets.

#include <nav_msgs/OccupancyGrid.h>

#include <fstream>
#include <mutex>

#include "tests/daemon/daemon_e2e.h"
#include "tests/ros/ros_fixture.h"

namespace {

using namespace sb::test;
using namespace sb::test::ros_e2e;
using sb::test::e2e::fixture;

}  // namespace

TEST_CASE("slambooster_ros publishes the daemon's navigation grid on ~map", "[ros][e2e]") {
  e2e::TempDir tmp;
  const std::string socket = tmp.path + "/sb.sock";
  const std::string settings = tmp.path + "/navmap.json";
  std::ofstream(settings) << R"({"up": "mount", "mount_height_m": 1.0, "mount_pitch_deg": 0.0})";
  RosMaster master(tmp.path);
  joinMaster(master, "test_map_subscriber");
  ros::NodeHandle node;
  std::mutex mutex;
  std::vector<nav_msgs::OccupancyGrid> grids;
  auto sub = node.subscribe<nav_msgs::OccupancyGrid>("/slambooster/map", 10,
                                                     [&](const nav_msgs::OccupancyGrid::ConstPtr& m) {
                                                       std::lock_guard lock(mutex);
                                                       grids.push_back(*m);
                                                     });
  ros::AsyncSpinner spinner(1);
  spinner.start();
  auto bridge = startBridge(master, {"socket:=" + socket, "reconnect_s:=0.05", "map_period_s:=0.2"},
                            tmp.path + "/bridge.log");
  INFO(bridge->log());
  REQUIRE(waitFor([&] { return sub.getNumPublishers() >= 1; }, 20.0));
  std::vector<std::string> args = e2e::daemonArgs(socket, tmp.path + "/out", "recorded", "stop");
  for (const std::string& set : {"output.navmap=" + settings, std::string("output.navmap_period_s=0.5")}) {
    args.push_back("--set");
    args.push_back(set);
  }
  ChildProcess daemon(args, {}, tmp.path + "/daemon.log");
  INFO(daemon.log());
  REQUIRE(waitFor([&] {
    std::lock_guard lock(mutex);
    return !grids.empty();
  }, 60.0));
  std::lock_guard lock(mutex);
  const nav_msgs::OccupancyGrid& g = grids.back();
  CHECK(g.header.frame_id == "slambooster_grid");
  CHECK(g.info.resolution == Approx(0.05));
  REQUIRE(g.info.width > 0);
  REQUIRE(g.data.size() == size_t(g.info.width) * g.info.height);
  size_t occupied = 0, free = 0;
  for (int8_t c : g.data) {
    CHECK((c == -1 || c == 0 || c == 100));
    occupied += c == 100, free += c == 0;
  }
  CHECK(occupied > 0);
  CHECK(free > 0);
}
