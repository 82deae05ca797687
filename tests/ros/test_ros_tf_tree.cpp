// The robot's TF tree with the bridge (issue 57, REP 105), against a real ROS master and the real daemon: a
// fake base publishes a synthetic corridor drive's odometry as nav_msgs/Odometry on /odom and as odom ->
// base_link on /tf, with the camera mount base_link -> camera_depth_optical_frame on /tf_static; the drive's
// depth goes over the bridge into the daemon's push source (as in test_ros_odometry_topic). Then, through tf2
// alone: map -> base_link at every frame's stamp equals the daemon's pose (trajectory.tum) composed with the
// inverse mount within 1 mm and 1 mrad; no frame has two parents; the bridge publishes map -> odom and never
// odom -> base_link; ~odometry is the base's pose in map (child_frame_id base_link) and equals the tree.
// A relocalisation cannot be provoked on cue in this drive (it tracks throughout): test_ros_tf_relocalisation
// scripts one through a stand-in daemon.
//
// Frame 0 is processed before any odometry is published (its processing opens the daemon's socket, which the
// bridge's pushes need), so the bridge still has map -> slambooster_camera for it: the tree is checked from
// frame 1 on.

#include <diagnostic_msgs/DiagnosticArray.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/CameraInfo.h>
#include <signal.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <algorithm>
#include <cmath>
#include <mutex>

#include "client/connection.h"
#include "drivers/sequence.h"
#include "tests/daemon/daemon_e2e.h"
#include "tests/ros/bag_writer.h"
#include "tests/ros/ros_fixture.h"
#include "tests/ros/tf_recorder.h"

namespace {

using namespace sb::test;
using namespace sb::test::ros_e2e;
using sb::test::e2e::kDaemon;
using sb::test::e2e::kTool;

constexpr int kDriveFrames = 120;
constexpr size_t kOdometryChunk =
    40;  // samples published before waiting for the bridge: within its queue of 100
constexpr const char* kCameraFrame = "camera_depth_optical_frame";
constexpr double kPositionTolM = 1e-3;    // the 1 mm
constexpr double kRotationTolRad = 1e-3;  // and 1 mrad
constexpr double kStampTolS = 1e-6;       // trajectory.tum's stamps against the bridge's (POSE's, a double)

// The bridge's ~odometry messages, by stamp.
struct OdometryLog {
  std::mutex mutex;
  std::map<ros::Time, nav_msgs::Odometry> messages;
  void on(const nav_msgs::Odometry::ConstPtr& m) {
    std::lock_guard lock(mutex);
    messages[m->header.stamp] = *m;
  }
};

// The bridge's `slambooster: odometry in` counts, from /diagnostics.
struct ForwarderCounts {
  std::mutex mutex;
  std::map<std::string, std::string> values;
  size_t get(const std::string& key) {
    std::lock_guard lock(mutex);
    const auto it = values.find(key);
    return it == values.end() ? 0 : std::stoul(it->second);
  }
  void onDiagnostics(const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
    std::lock_guard lock(mutex);
    for (const auto& s : m->status)
      if (s.name == "slambooster: odometry in")
        for (const auto& kv : s.values) values[kv.key] = kv.value;
  }
};

}  // namespace

TEST_CASE(
    "map -> odom -> base_link through tf2 is the daemon's pose composed with the mount, frame for frame",
    "[ros][e2e][tf]") {
  const std::string dir = scratchDir("ros_tf_tree");
  const std::string drive = dir + "/drive";
  const auto synth = runCommand(
      kTool + " synth --scene corridor --stress drive --seed 0 --frames " + std::to_string(kDriveFrames) +
      " --width 160 --height 120 --fx 120.3 --fy 120 --threads 1 --overwrite --out " + drive);
  INFO(synth.output);
  REQUIRE(synth.exitCode == 0);
  const std::string config = pipelineConfigWithHints(dir, drive, 128, "csr=1,ir=1");

  sb::SequenceOptions o;
  o.prefetch = false;
  auto source = sb::openSequence(drive, o);
  const sb::SequenceInfo info = source->info();
  std::vector<sb::DepthFrame> frames;
  while (auto f = source->next()) frames.push_back(std::move(*f));
  REQUIRE(frames.size() == static_cast<size_t>(kDriveFrames));
  const std::vector<nav_msgs::Odometry> odometry =
      odometryMessages(drive + "/odometry.txt", /*covariance=*/false);
  REQUIRE(odometry.size() > frames.size());
  const Eigen::Isometry3d mount = parsePose(kBagCameraMount);

  e2e::TempDir tmp;
  const std::string socket = tmp.path + "/sb.sock", push = tmp.path + "/push.sock";
  RosMaster master(tmp.path);
  joinMaster(master, "test_tf_tree");
  ros::NodeHandle node;
  ros::Publisher depthPub = node.advertise<sensor_msgs::Image>("/camera/depth/image", 2);
  ros::Publisher infoPub =
      node.advertise<sensor_msgs::CameraInfo>("/camera/depth/camera_info", 1, /*latch=*/true);
  ros::Publisher odomPub = node.advertise<nav_msgs::Odometry>("/odom", 1000);
  ros::Publisher tfPub = node.advertise<tf2_msgs::TFMessage>("/tf", 100);
  ros::Publisher tfStaticPub = node.advertise<tf2_msgs::TFMessage>("/tf_static", 1, /*latch=*/true);
  OdometryLog bridgeOdometry;
  auto odometrySub = node.subscribe("/slambooster/odometry", 1000, &OdometryLog::on, &bridgeOdometry);
  ForwarderCounts counts;
  auto diagnostics = node.subscribe("/diagnostics", 100, &ForwarderCounts::onDiagnostics, &counts);
  TfRecorder recorder(node);
  tf2_ros::Buffer buffer(ros::Duration(600));  // the whole drive
  tf2_ros::TransformListener listener(buffer);
  ros::AsyncSpinner spinner(1);
  spinner.start();
  sensor_msgs::CameraInfo ci;
  ci.width = static_cast<uint32_t>(info.intrinsics.width);
  ci.height = static_cast<uint32_t>(info.intrinsics.height);
  ci.K = {info.intrinsics.fx, 0, info.intrinsics.cx, 0, info.intrinsics.fy, info.intrinsics.cy, 0, 0, 1};
  infoPub.publish(ci);
  tfStaticPub.publish(cameraMountMessage(kCameraFrame, ros::Time(0.001)));

  auto bridge = startBridge(
      master,
      {"socket:=" + socket, "push_socket:=" + push, "depth_topic:=/camera/depth/image",
       "push_depth_scale:=" + std::to_string(info.depthScale), "reconnect_s:=0.05", "odom_topic:=/odom",
       std::string("odom_camera_frame:=") + kCameraFrame, "transform_tolerance:=0.1"},
      tmp.path + "/bridge.log");
  INFO(bridge->log());
  REQUIRE(waitFor(
      [&] {
        return depthPub.getNumSubscribers() >= 1 && infoPub.getNumSubscribers() >= 1 &&
               odomPub.getNumSubscribers() >= 1 && tfStaticPub.getNumSubscribers() >= 2 &&
               tfPub.getNumSubscribers() >= 2 && odometrySub.getNumPublishers() >= 1;
      },
      20.0));
  std::this_thread::sleep_for(std::chrono::seconds(2));  // the latched mount reaches the bridge's tf2 buffer

  ChildProcess daemon({kDaemon,
                       "--input",
                       push,
                       "--out",
                       tmp.path + "/pushed",
                       "--socket",
                       socket,
                       "--pacing",
                       "recorded",
                       "--at-end",
                       "stop",
                       "--controller",
                       "fixed",
                       "--set",
                       "slam.threads=1",
                       "--set",
                       "slam.pipeline_config=" + config,
                       "--set",
                       "source.type=push",
                       "--set",
                       "output.rotation.mode=never"},
                      {}, tmp.path + "/daemon.log");
  INFO(daemon.log());
  REQUIRE(waitFor([&] { return waitForPath(push, 0.01); }, 30.0));
  std::unique_ptr<sb::client::Connection> client;
  const auto processed = [&](size_t n) {
    client->send("?POLL;");
    return client->reply("POLL", 10.0).value("frames", size_t{0}) >= n;
  };
  for (size_t i = 0; i < frames.size(); ++i) {
    depthPub.publish(depthImage(frames[i], info.depthScale, ros::Time(frames[i].timestamp)));
    if (!client) {
      REQUIRE(waitForPath(socket, 30.0));
      client = std::make_unique<sb::client::Connection>(socket, 10.0);
    }
    INFO("frame " << i);
    REQUIRE(waitFor([&] { return processed(i + 1); }, 30.0));
    if (i != 0) continue;
    // The base: every sample on /odom, and the same poses as odom -> base_link on /tf, in chunks.
    tf2_msgs::TFMessage tf;
    for (size_t k = 0; k < odometry.size(); ++k) {
      geometry_msgs::TransformStamped t;
      t.header = odometry[k].header;
      t.child_frame_id = odometry[k].child_frame_id;
      t.transform.translation.x = odometry[k].pose.pose.position.x;
      t.transform.translation.y = odometry[k].pose.pose.position.y;
      t.transform.translation.z = odometry[k].pose.pose.position.z;
      t.transform.rotation = odometry[k].pose.pose.orientation;
      tf.transforms.push_back(t);
      if ((k + 1) % kOdometryChunk != 0 && k + 1 != odometry.size()) continue;
      tfPub.publish(tf);
      tf.transforms.clear();
      for (size_t j = k - (k % kOdometryChunk); j <= k; ++j) odomPub.publish(odometry[j]);
      INFO("odometry samples published: " << k + 1);
      REQUIRE(waitFor(
          [&] {
            return counts.get("pushed") + counts.get("skipped_no_mount") + counts.get("failed") >= k + 1;
          },
          20.0));
    }
    REQUIRE(counts.get("pushed") == odometry.size());
  }
  client.reset();
  daemon.signal(SIGTERM);
  REQUIRE(daemon.wait(30.0) == 0);
  const auto trajectory = trajectoryLines(tmp.path + "/pushed/trajectory.tum");
  REQUIRE(trajectory.size() >= frames.size() - 2);
  const ros::Time last(lineValues(trajectory.back())[0]);
  // In sync when the bridge's ~odometry holds the last frame's pose (one publisher, one connection: the messages
  // arrive in order, so any earlier one missing then was dropped, not late, and the per-frame checks below name
  // it). Frame 0 (published before the bridge's watch may have connected) is not checked.
  const auto bridgeHasLast = [&] {
    std::lock_guard lock(bridgeOdometry.mutex);
    return !bridgeOdometry.messages.empty() &&
           bridgeOdometry.messages.rbegin()->first >= last - ros::Duration(kStampTolS);
  };
  const bool inSync = waitFor([&] { return buffer.canTransform("map", "odom", last) && bridgeHasLast(); }, 20.0);
  {
    std::lock_guard lock(bridgeOdometry.mutex);
    INFO("the bridge's ~odometry: " << bridgeOdometry.messages.size() << " messages for " << trajectory.size()
                                    << " trajectory lines");
    REQUIRE(inSync);
  }

  size_t checked = 0;
  double worstM = 0.0, worstRad = 0.0;
  for (size_t i = 0; i < trajectory.size(); ++i) {
    const std::vector<double> v = lineValues(trajectory[i]);
    const ros::Time stamp(v[0]);
    // Frame 0 (before the odometry was published) and a frame before the odometry's first sample (no odom ->
    // base_link at its stamp: the bridge has no map -> odom yet) are not in the tree; every other frame is.
    if (stamp <= ros::Time(frames[0].timestamp) || stamp < odometry.front().header.stamp) continue;
    INFO("trajectory line " << i << ": " << trajectory[i]);
    Eigen::Isometry3d daemonPose = Eigen::Isometry3d::Identity();
    daemonPose.linear() = Eigen::Quaterniond(v[7], v[4], v[5], v[6]).normalized().toRotationMatrix();
    daemonPose.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    const Eigen::Isometry3d expected = daemonPose * mount.inverse();
    const Eigen::Isometry3d tree = toIsometry(buffer.lookupTransform("map", "base_link", stamp).transform);
    CHECK(translationError(tree, expected) < kPositionTolM);
    CHECK(rotationError(tree, expected) < kRotationTolRad);
    worstM = std::max(worstM, translationError(tree, expected));
    worstRad = std::max(worstRad, rotationError(tree, expected));
    // ~odometry: the base in map, the same pose as the tree
    std::lock_guard lock(bridgeOdometry.mutex);
    const auto it = bridgeOdometry.messages.lower_bound(stamp - ros::Duration(kStampTolS));
    REQUIRE(it != bridgeOdometry.messages.end());
    REQUIRE(std::abs((it->first - stamp).toSec()) < kStampTolS);
    CHECK(it->second.header.frame_id == "map");
    CHECK(it->second.child_frame_id == "base_link");
    const auto& p = it->second.pose.pose;
    geometry_msgs::Transform asTransform;
    asTransform.translation.x = p.position.x;
    asTransform.translation.y = p.position.y;
    asTransform.translation.z = p.position.z;
    asTransform.rotation = p.orientation;
    CHECK(translationError(toIsometry(asTransform), expected) < kPositionTolM);
    CHECK(rotationError(toIsometry(asTransform), expected) < kRotationTolRad);
    ++checked;
  }
  CHECK(checked >= trajectory.size() - 2);
  WARN(checked << " frames: map -> base_link through tf2 against the daemon's pose with the mount: largest "
               << worstM * 1e3 << " mm, " << worstRad * 1e3 << " mrad");

  // One parent per frame; the bridge publishes map -> odom (and its own grid/camera frames), never the
  // base's.
  for (const auto& [child, parents] : recorder.parents()) {
    INFO(child << " has parents " << parents.size() << ": " << *parents.begin() << " ...");
    CHECK(parents.size() == 1);
  }
  const std::set<std::string> bridgeEdges = recorder.edgesOf("/slambooster");
  CHECK(bridgeEdges.count("map -> odom") == 1);
  for (const std::string& e : bridgeEdges) {
    INFO("the bridge published " << e);
    CHECK((e == "map -> odom" || e == "map -> slambooster_camera" || e == "map -> slambooster_grid"));
  }
  CHECK(recorder.edgesOf("/test_tf_tree").count("odom -> base_link") == 1);
  bridge->signal(SIGINT);
  CHECK(bridge->wait(10.0) == 0);
  spinner.stop();
  ros::shutdown();
}
