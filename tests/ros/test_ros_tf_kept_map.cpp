// A restart in a kept map in the bridge's TF (issue 55, docs/map-store.md; REP 105), against a real ROS master: a
// stand-in daemon (tests/ros/fake_daemon.h) serves frames 0-4 localising in the kept map (state lost, the pose held
// at the start, in no frame of the store) and frames 5-9 localised (the store's frame, a jump of metres from the
// held pose). Without the robot's odometry the bridge's edge is map -> ~camera_frame: it is not sent while
// localising (a lookup at those stamps finds nothing; diagnostics say why) and is the daemon's pose from the
// localised frame on. (With odometry the localising frames are lost, so map -> odom is not sent before the
// localised frame, whose jump goes into it: ros/map_to_odom.h, test_ros_tf_relocalisation.cpp.)

#include <signal.h>
#include <tf2/exceptions.h>

#include <nlohmann/json.hpp>

#include "tests/daemon/daemon_e2e.h"
#include "tests/ros/fake_daemon.h"
#include "tests/ros/ros_fixture.h"
#include "tests/ros/tf_recorder.h"

namespace {

using namespace sb::test;
using namespace sb::test::ros_e2e;

constexpr int kFrames = 10, kLocalisedAt = 5;
constexpr double kStartS = 100.0, kPeriodS = 0.1;
constexpr double kTol = 1e-6;

// The camera in the store's frame at frame k (optical axes; the robot 2.5 m along the store's x).
Eigen::Isometry3d inStore(int k) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(2.5 + 0.05 * k, 0.1, 0.4);
  return T;
}

}  // namespace

TEST_CASE("localising in a kept map sends no map -> camera edge; the localised frames do, in the store's frame",
          "[ros][e2e][tf]") {
  e2e::TempDir tmp;
  const std::string socket = tmp.path + "/sb.sock";
  FakeDaemon daemon(socket);
  RosMaster master(tmp.path);
  joinMaster(master, "test_tf_kept_map");
  ros::NodeHandle node;
  TfWatch watch(node);
  auto bridge = startBridge(master, {"socket:=" + socket, "reconnect_s:=0.05", "map_period_s:=0", "cloud_period_s:=0"},
                            tmp.path + "/bridge.log");
  INFO(bridge->log());
  REQUIRE(waitFor([&] { return watch.diagnosticsSub.getNumPublishers() >= 1 && daemon.watched(); }, 20.0));

  for (int k = 0; k < kFrames; ++k) {
    const bool localised = k >= kLocalisedAt;
    // While localising the daemon holds its start pose (the identity): in no frame of the store.
    const Eigen::Isometry3d camera = localised ? inStore(k) : Eigen::Isometry3d::Identity();
    const Eigen::Quaterniond q(camera.linear());
    daemon.report(nlohmann::json{{"class", "POSE"},
                                 {"frame", k},
                                 {"timestamp", kStartS + kPeriodS * k},
                                 {"position", {camera.translation().x(), camera.translation().y(),
                                               camera.translation().z()}},
                                 {"quaternion", {q.x(), q.y(), q.z(), q.w()}},
                                 {"tracked", localised},
                                 {"state", localised ? (k == kLocalisedAt ? "relocalised" : "good") : "lost"},
                                 {"kept_map", localised ? "localised" : "localising"}}
                      .dump());
    daemon.report(nlohmann::json{
        {"class", "KNOBS"}, {"frame", k}, {"csr", 1}, {"icp", 1}, {"pd", {1, 1, 1}}, {"tr", 1}, {"ir", 1}}
                      .dump());
    INFO("frame " << k);
    REQUIRE(waitFor([&] { return watch.diagnostics.of(k).has_value(); }, 10.0));
  }
  const ros::Time last(kStartS + kPeriodS * (kFrames - 1));
  REQUIRE(waitFor([&] { return watch.buffer.canTransform("map", "slambooster_camera", last); }, 10.0));
  for (int k = 0; k < kFrames; ++k) {
    INFO("frame " << k);
    const ros::Time stamp(kStartS + kPeriodS * k);
    if (k < kLocalisedAt) {
      CHECK(diagnosticValue(*watch.diagnostics.of(k), "tf") == "none: localising in the kept map");
      CHECK_FALSE(watch.buffer.canTransform("map", "slambooster_camera", stamp));
    } else {
      CHECK(diagnosticValue(*watch.diagnostics.of(k), "tf") == "map -> slambooster_camera");
      const Eigen::Isometry3d camera =
          toIsometry(watch.buffer.lookupTransform("map", "slambooster_camera", stamp).transform);
      CHECK(translationError(camera, inStore(k)) < kTol);
      CHECK(rotationError(camera, inStore(k)) < kTol);
    }
  }
  CHECK(watch.recorder.edgesOf("/slambooster") == std::set<std::string>{"map -> slambooster_camera"});
  bridge->signal(SIGINT);
  CHECK(bridge->wait(10.0) == 0);
  watch.spinner.stop();
  ros::shutdown();
}
