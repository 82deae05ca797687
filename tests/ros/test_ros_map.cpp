// ~map, ~cloud, the grid's TF and ~octomap end to end against a real ROS master (issue 45): the daemon replays
// the short synthetic sequence with a navigation map (a camera mount says which way is up), writes its grid,
// map_frame.json and map.bt every 0.5 s and answers ?MAP and ?CLOUD; the bridge publishes the grid latched on
// ~map, the surface cloud on ~cloud, ~map_frame -> ~grid_frame on /tf_static and map.bt's path as ~octomap;
// this program subscribes and checks what it gets against the daemon's files.

#include <nav_msgs/OccupancyGrid.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
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
  std::vector<sensor_msgs::PointCloud2> clouds;
  auto cloudSub = node.subscribe<sensor_msgs::PointCloud2>("/slambooster/cloud", 10,
                                                          [&](const sensor_msgs::PointCloud2::ConstPtr& m) {
                                                            std::lock_guard lock(mutex);
                                                            clouds.push_back(*m);
                                                          });
  tf2_ros::Buffer tfBuffer;
  tf2_ros::TransformListener tfListener(tfBuffer);
  auto sub = node.subscribe<nav_msgs::OccupancyGrid>("/slambooster/map", 10,
                                                     [&](const nav_msgs::OccupancyGrid::ConstPtr& m) {
                                                       std::lock_guard lock(mutex);
                                                       grids.push_back(*m);
                                                     });
  ros::AsyncSpinner spinner(1);
  spinner.start();
  auto bridge = startBridge(master, {"socket:=" + socket, "reconnect_s:=0.05", "map_period_s:=0.2", "cloud_period_s:=0.2"},
                            tmp.path + "/bridge.log");
  INFO(bridge->log());
  REQUIRE(waitFor([&] { return sub.getNumPublishers() >= 1 && cloudSub.getNumPublishers() >= 1; }, 20.0));
  std::vector<std::string> args = e2e::daemonArgs(socket, tmp.path + "/out", "recorded", "stop");
  for (const std::string& set : {"output.navmap=" + settings, std::string("output.navmap_period_s=0.5")}) {
    args.push_back("--set");
    args.push_back(set);
  }
  ChildProcess daemon(args, {}, tmp.path + "/daemon.log");
  INFO(daemon.log());
  REQUIRE(waitFor([&] {
    std::lock_guard lock(mutex);
    return !grids.empty() && !clouds.empty();
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

  // ~cloud: the surface cells' centres in the grid's frame, inside the grid's extent (a cloud cell's half side
  // of slack), some in the robot's band.
  const sensor_msgs::PointCloud2& c = clouds.back();
  CHECK(c.header.frame_id == "slambooster_grid");
  REQUIRE(c.width * c.height > 0);
  const double minX = g.info.origin.position.x, minY = g.info.origin.position.y;
  const double maxX = minX + g.info.width * g.info.resolution, maxY = minY + g.info.height * g.info.resolution;
  size_t inBand = 0, outside = 0;
  for (sensor_msgs::PointCloud2ConstIterator<float> x(c, "x"), y(c, "y"), z(c, "z"); x != x.end(); ++x, ++y, ++z) {
    REQUIRE((std::isfinite(*x) && std::isfinite(*y) && std::isfinite(*z)));
    outside += *x < minX - 0.2 || *x > maxX + 0.2 || *y < minY - 0.2 || *y > maxY + 0.2;
    inBand += *z > 0.1 && *z < 1.5;
  }
  CHECK(outside == 0);
  CHECK(inBand > 0);

  // The grid's frame on /tf_static: the inverse of the daemon's map_frame.json (T_world_to_map).
  std::string passDir;
  for (const auto& e : std::filesystem::recursive_directory_iterator(tmp.path + "/out"))
    if (e.path().filename() == "map_frame.json") passDir = e.path().parent_path().string();
  REQUIRE(!passDir.empty());
  const nlohmann::json frame = nlohmann::json::parse(std::ifstream(passDir + "/map_frame.json"));
  Eigen::Matrix4d worldToMap;
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < 4; ++k) worldToMap(r, k) = frame.at("T_world_to_map").at(r).at(k).get<double>();
  REQUIRE(waitFor([&] { return tfBuffer.canTransform("map", "slambooster_grid", ros::Time(0)); }, 10.0));
  const auto t = tfBuffer.lookupTransform("map", "slambooster_grid", ros::Time(0)).transform;
  Eigen::Isometry3d mapInWorld = Eigen::Isometry3d::Identity();
  mapInWorld.linear() = Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z).toRotationMatrix();
  mapInWorld.translation() = Eigen::Vector3d(t.translation.x, t.translation.y, t.translation.z);
  CHECK((mapInWorld.matrix() * worldToMap - Eigen::Matrix4d::Identity()).cwiseAbs().maxCoeff() < 1e-9);

  // ~octomap: map.bt's path, set exactly when the daemon wrote one (a build with liboctomap).
  std::string octomap;
  const bool haveBt = std::filesystem::exists(passDir + "/map.bt");
  if (haveBt) CHECK(waitFor([&] { return ros::param::get("/slambooster/octomap", octomap); }, 10.0));
  CHECK(ros::param::get("/slambooster/octomap", octomap) == haveBt);
  if (haveBt) CHECK(std::filesystem::equivalent(octomap, passDir + "/map.bt"));
}
