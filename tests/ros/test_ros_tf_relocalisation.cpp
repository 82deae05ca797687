// A relocalisation and a lost stretch in the robot's TF tree (issue 57, REP 105), against a real ROS master:
// the real daemon cannot be made to relocalise on cue, so a stand-in (tests/ros/fake_daemon.h) serves the
// bridge a scripted POSE stream while a fake base publishes /odom and odom -> base_link on /tf, and the mount
// on /tf_static. The daemon's pose is map_T_odom * odom_T_base * mount with map_T_odom = A for frames 0-4,
// frames 5-6 lost (the pose held), then a relocalisation to map_T_odom = B from frame 7 on. Through tf2: map
// -> odom is A, held at A on the lost frames (diagnostics say so), B after the jump; odom -> base_link stays
// the base's, and only the base publishes it; map -> base_link is the daemon's pose with the inverse mount on
// tracked frames; the last map -> odom is also stamped ~transform_tolerance later (a lookup at "now" between
// frames succeeds) and not beyond.

#include <nav_msgs/Odometry.h>
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

constexpr int kFrames = 10;
constexpr double kStartS = 100.0, kPeriodS = 0.1;  // the frames' stamps
constexpr double kToleranceS = 0.1;                // ~transform_tolerance given to the bridge
constexpr double kTol = 1e-6;  // metres / radians: the bridge's arithmetic, doubles and floats of TF

Eigen::Isometry3d pose(double x, double y, double yawRad) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yawRad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, 0.0);
  return T;
}

Eigen::Isometry3d baseInOdom(int k) {
  return pose(0.2 * k, 0.01 * k * k, 0.04 * k);
}

std::string state(int k) {
  return k == 5 || k == 6 ? "lost" : k == 7 ? "relocalised" : "good";
}

}  // namespace

TEST_CASE("a relocalisation moves map -> odom and not odom -> base_link; a lost stretch holds map -> odom",
          "[ros][e2e][tf]") {
  const Eigen::Isometry3d mount = parsePose("0 0 1.25 -0.5 0.5 -0.5 0.5");
  const Eigen::Isometry3d A = pose(0.3, -0.2, 0.05), B = pose(-0.4, 0.5, -0.2);
  e2e::TempDir tmp;
  const std::string socket = tmp.path + "/sb.sock";
  FakeDaemon daemon(socket);
  RosMaster master(tmp.path);
  joinMaster(master, "test_tf_base");
  ros::NodeHandle node;
  ros::Publisher odomPub = node.advertise<nav_msgs::Odometry>("/odom", 100);
  ros::Publisher tfPub = node.advertise<tf2_msgs::TFMessage>("/tf", 100);
  ros::Publisher tfStaticPub = node.advertise<tf2_msgs::TFMessage>("/tf_static", 1, /*latch=*/true);
  TfWatch watch(node);
  tf2_msgs::TFMessage mountMessage;
  mountMessage.transforms.resize(1);
  mountMessage.transforms[0].header.frame_id = "base_link";
  mountMessage.transforms[0].child_frame_id = "camera_depth_optical_frame";
  mountMessage.transforms[0].transform = toTransform(mount);
  tfStaticPub.publish(mountMessage);

  auto bridge = startBridge(
      master,
      {"socket:=" + socket, "reconnect_s:=0.05", "odom_topic:=/odom",
       "camera_frame:=camera_depth_optical_frame", "odom_camera_frame:=camera_depth_optical_frame",
       "map_period_s:=0", "cloud_period_s:=0", "transform_tolerance:=" + std::to_string(kToleranceS)},
      tmp.path + "/bridge.log");
  INFO(bridge->log());
  REQUIRE(waitFor(
      [&] {
        return odomPub.getNumSubscribers() >= 1 && tfStaticPub.getNumSubscribers() >= 2 &&
               watch.diagnosticsSub.getNumPublishers() >= 1 && daemon.watched();
      },
      20.0));
  std::this_thread::sleep_for(std::chrono::seconds(1));  // the latched mount reaches the bridge's tf2 buffer

  // Before any odometry the bridge has no odom frame; its ~camera_frame here is the robot's camera frame
  // (parent base_link, from /tf_static), which it must not give a second parent: no edge, and it says why.
  const auto sendFrame = [&](int frame, double stampS, const Eigen::Isometry3d& camera,
                             const std::string& st) {
    const Eigen::Quaterniond q(camera.linear());
    daemon.report(nlohmann::json{
        {"class", "POSE"},
        {"frame", frame},
        {"timestamp", stampS},
        {"position", {camera.translation().x(), camera.translation().y(), camera.translation().z()}},
        {"quaternion", {q.x(), q.y(), q.z(), q.w()}},
        {"tracked", st != "lost"},
        {"state", st}}.dump());
    daemon.report(nlohmann::json{
        {"class", "KNOBS"}, {"frame", frame}, {"csr", 1}, {"icp", 1}, {"pd", {1, 1, 1}}, {"tr", 1}, {"ir", 1}}
                      .dump());
  };
  sendFrame(99, kStartS - 1.0, mount, "good");
  REQUIRE(waitFor([&] { return watch.diagnostics.of(99).has_value(); }, 10.0));
  CHECK(diagnosticValue(*watch.diagnostics.of(99), "tf") ==
        "none: ~camera_frame 'camera_depth_optical_frame' has the parent 'base_link' in TF; leave "
        "~camera_frame at "
        "slambooster_camera");

  // The base: the whole drive's odometry first (TF, then /odom: the bridge pushes each sample to the
  // "daemon").
  tf2_msgs::TFMessage tf;
  std::vector<nav_msgs::Odometry> odometry;
  for (int k = 0; k < kFrames; ++k) {
    geometry_msgs::TransformStamped t;
    t.header.stamp = ros::Time(kStartS + kPeriodS * k);
    t.header.frame_id = "odom";
    t.child_frame_id = "base_link";
    t.transform = toTransform(baseInOdom(k));
    tf.transforms.push_back(t);
    nav_msgs::Odometry o;
    o.header = t.header;
    o.child_frame_id = t.child_frame_id;
    o.pose.pose.position.x = t.transform.translation.x;
    o.pose.pose.position.y = t.transform.translation.y;
    o.pose.pose.position.z = t.transform.translation.z;
    o.pose.pose.orientation = t.transform.rotation;
    odometry.push_back(o);
  }
  tfPub.publish(tf);
  REQUIRE(waitFor(
      [&] {
        return watch.buffer.canTransform("odom", "base_link", ros::Time(kStartS + kPeriodS * (kFrames - 1)));
      },
      10.0));
  for (const auto& o : odometry) odomPub.publish(o);
  REQUIRE(waitFor([&] { return daemon.odometrySamples() == static_cast<size_t>(kFrames); }, 10.0));

  // The daemon: each frame's POSE and KNOBS, one frame at a time.
  Eigen::Isometry3d held = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Isometry3d> daemonPoses;
  for (int k = 0; k < kFrames; ++k) {
    const Eigen::Isometry3d mapToOdom = k < 5 ? A : B;
    const Eigen::Isometry3d camera = state(k) == "lost" ? held : mapToOdom * baseInOdom(k) * mount;
    if (state(k) != "lost") held = camera;
    daemonPoses.push_back(camera);
    sendFrame(k, kStartS + kPeriodS * k, camera, state(k));
    INFO("frame " << k);
    REQUIRE(waitFor([&] { return watch.diagnostics.of(k).has_value(); }, 10.0));
  }
  const ros::Time last(kStartS + kPeriodS * (kFrames - 1));
  REQUIRE(waitFor([&] { return watch.buffer.canTransform("map", "odom", last); }, 10.0));

  for (int k = 0; k < kFrames; ++k) {
    INFO("frame " << k << " (" << state(k) << ")");
    const ros::Time stamp(kStartS + kPeriodS * k);
    const Eigen::Isometry3d mapToOdom =
        toIsometry(watch.buffer.lookupTransform("map", "odom", stamp).transform);
    const Eigen::Isometry3d expected = k < 7 ? A : B;  // lost frames 5-6 hold A
    CHECK(translationError(mapToOdom, expected) < kTol);
    CHECK(rotationError(mapToOdom, expected) < kTol);
    const Eigen::Isometry3d odomToBase =
        toIsometry(watch.buffer.lookupTransform("odom", "base_link", stamp).transform);
    CHECK(translationError(odomToBase, baseInOdom(k)) < kTol);  // the base's own, untouched by the jump
    CHECK(rotationError(odomToBase, baseInOdom(k)) < kTol);
    if (state(k) != "lost") {
      const Eigen::Isometry3d base =
          toIsometry(watch.buffer.lookupTransform("map", "base_link", stamp).transform);
      CHECK(translationError(base, daemonPoses[size_t(k)] * mount.inverse()) < kTol);
      CHECK(rotationError(base, daemonPoses[size_t(k)] * mount.inverse()) < kTol);
    }
    const auto d = watch.diagnostics.of(k);
    REQUIRE(d);
    CHECK(diagnosticValue(*d, "tf") == "map -> odom");
    if (state(k) == "lost") {
      CHECK(d->level == diagnostic_msgs::DiagnosticStatus::ERROR);
      CHECK(diagnosticValue(*d, "map_to_odom") == "held since frame 4: lost");
      CHECK(d->message.find("map -> odom held since frame 4: lost") != std::string::npos);
    } else {
      CHECK(diagnosticValue(*d, "map_to_odom") == "updated");
    }
  }
  // The jump is in map -> odom, by what the relocalisation corrected.
  CHECK(translationError(A, B) > 0.5);

  // Forward-dated: a lookup between the last frame and last + tolerance finds the last map -> odom; past it
  // none.
  for (const double after : {0.05, kToleranceS}) {
    INFO("last frame + " << after << " s");
    const auto t = watch.buffer.lookupTransform("map", "odom", last + ros::Duration(after));
    CHECK(translationError(toIsometry(t.transform), B) < kTol);
  }
  CHECK_THROWS_AS(watch.buffer.lookupTransform("map", "odom", last + ros::Duration(kToleranceS + 0.05)),
                  tf2::ExtrapolationException);

  for (const auto& [child, parents] : watch.recorder.parents()) {
    INFO(child << " has " << parents.size() << " parents");
    CHECK(parents.size() == 1);
  }
  const std::set<std::string> bridgeEdges = watch.recorder.edgesOf("/slambooster");
  CHECK(bridgeEdges == std::set<std::string>{"map -> odom"});
  CHECK(watch.recorder.edgesOf("/test_tf_base") ==
        std::set<std::string>{"odom -> base_link", "base_link -> camera_depth_optical_frame"});
  bridge->signal(SIGINT);
  CHECK(bridge->wait(10.0) == 0);
  watch.spinner.stop();
  ros::shutdown();
}
