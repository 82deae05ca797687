// A robot's bag replayed through the bridge (issue 57's last "done when"): a synthetic corridor drive recorded
// as a robot records it (depth and CameraInfo, the base's nav_msgs/Odometry on /odom and the same poses as
// odom -> base_link on /tf, the camera mount base_link -> openni_depth_optical_frame on /tf_static), written
// with the rosbag C++ API and played back onto a real master message by message in the bag's order (what
// `rosbag play` does; the test is the player, pacing it frame by frame so that the live push source drops no
// frame, the base's messages up to kLeadS ahead of the frames). The bridge pushes the depth into the daemon and publishes map -> odom. Then `map` -> `base_link`,
// looked up through tf2 at every frame's stamp (the lookup `tf2_echo map base_link` makes, which would print
// only the latest one a second), is within 1 cm and 10 mrad of the daemon's pose (trajectory.tum) composed
// with the inverse mount, at every frame from the second on (frame 0 is processed before the daemon's socket
// exists: no map -> odom for it yet; test_ros_tf_tree says why).
//
// tf2_echo and rosbag play are not used: Debian 12 packages them (tf2-tools, python3-rosbag) but tests/ros
// builds against the ROS packages scripts/install_deps.sh installs, which do not include them.

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <signal.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <algorithm>
#include <memory>

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

constexpr int kDriveFrames = 90;
constexpr const char* kCameraFrame = "openni_depth_optical_frame";  // the bag's image frame (bag_writer.cpp)
constexpr double kPositionTolM = 0.01;    // the 1 cm
constexpr double kRotationTolRad = 0.01;  // and 10 mrad
// Messages recorded up to this long after a depth frame go out before the test waits for that frame: the
// base's odometry just after a frame's stamp, which tf2 needs to place the base at that stamp (as a player at
// the recorded pace would have sent it long before the frame's pose comes back).
constexpr double kLeadS = 0.2;

}  // namespace

TEST_CASE("a robot's bag played through the bridge: map -> base_link is the daemon's pose with the mount",
          "[ros][e2e][tf][bag]") {
  const std::string dir = scratchDir("ros_bag_tf");
  const std::string drive = dir + "/drive";
  const auto synth = runCommand(
      kTool + " synth --scene corridor --stress drive --seed 0 --frames " + std::to_string(kDriveFrames) +
      " --width 160 --height 120 --fx 120.3 --fy 120 --threads 1 --overwrite --out " + drive);
  INFO(synth.output);
  REQUIRE(synth.exitCode == 0);
  const std::string config = pipelineConfigWithHints(dir, drive, 128, "csr=1,ir=1");
  BagSpec spec;
  spec.rgbTopic = false;
  spec.odometryFile = drive + "/odometry.txt";
  spec.odomTf = true;
  const std::string bagPath = dir + "/drive.bag";
  REQUIRE(writeBag(bagPath, drive, spec) == static_cast<size_t>(kDriveFrames));
  sb::SequenceOptions o;
  o.prefetch = false;
  const sb::SequenceInfo info = sb::openSequence(drive, o)->info();
  const Eigen::Isometry3d mount = parsePose(kBagCameraMount);

  e2e::TempDir tmp;
  const std::string socket = tmp.path + "/sb.sock", push = tmp.path + "/push.sock";
  RosMaster master(tmp.path);
  joinMaster(master, "test_bag_tf");
  ros::NodeHandle node;
  ros::Publisher depthPub = node.advertise<sensor_msgs::Image>(kBagDepthTopic, 2);
  ros::Publisher infoPub = node.advertise<sensor_msgs::CameraInfo>("/camera/depth/camera_info", 1, true);
  ros::Publisher odomPub = node.advertise<nav_msgs::Odometry>("/odom", 1000);
  ros::Publisher tfPub = node.advertise<tf2_msgs::TFMessage>("/tf", 1000);
  ros::Publisher tfStaticPub = node.advertise<tf2_msgs::TFMessage>("/tf_static", 1, /*latch=*/true);
  TfRecorder recorder(node);
  tf2_ros::Buffer buffer(ros::Duration(600));  // the whole drive
  tf2_ros::TransformListener listener(buffer);
  ros::AsyncSpinner spinner(1);
  spinner.start();

  auto bridge = startBridge(
      master,
      {"socket:=" + socket, "push_socket:=" + push, std::string("depth_topic:=") + kBagDepthTopic,
       "push_depth_scale:=" + std::to_string(info.depthScale), "reconnect_s:=0.05", "odom_topic:=/odom",
       std::string("odom_camera_frame:=") + kCameraFrame, "transform_tolerance:=0.1"},
      tmp.path + "/bridge.log");
  INFO(bridge->log());
  REQUIRE(waitFor(
      [&] {
        return depthPub.getNumSubscribers() >= 1 && infoPub.getNumSubscribers() >= 1 &&
               odomPub.getNumSubscribers() >= 1 && tfStaticPub.getNumSubscribers() >= 2 &&
               tfPub.getNumSubscribers() >= 2;
      },
      20.0));
  ChildProcess daemon({kDaemon, "--input", push, "--out", tmp.path + "/pushed", "--socket", socket, "--pacing",
                       "recorded", "--at-end", "stop", "--controller", "fixed", "--set", "slam.threads=1", "--set",
                       "slam.pipeline_config=" + config, "--set", "source.type=push", "--set",
                       "output.rotation.mode=never"},
                      {}, tmp.path + "/daemon.log");
  INFO(daemon.log());
  REQUIRE(waitFor([&] { return waitForPath(push, 0.01); }, 30.0));

  // The player: every message of the bag in its recorded order, on its topic.
  rosbag::Bag bag(bagPath, rosbag::bagmode::Read);
  rosbag::View view(bag);
  std::vector<rosbag::MessageInstance> messages(view.begin(), view.end());
  std::vector<ros::Time> depthTimes;
  for (const auto& m : messages)
    if (m.getTopic() == kBagDepthTopic) depthTimes.push_back(m.getTime());
  REQUIRE(depthTimes.size() == static_cast<size_t>(kDriveFrames));
  // Two cursors into the bag's order: the depth frames (with their CameraInfo) one at a time, the rest (the
  // base's odometry and TF) up to kLeadS past the frame.
  const auto isFrame = [](const rosbag::MessageInstance& m) {
    return m.getTopic() == kBagDepthTopic || m.getTopic() == "/camera/depth/camera_info";
  };
  size_t nextFrame = 0, nextOther = 0;
  const auto publish = [&](const rosbag::MessageInstance& m) {
    if (m.getTopic() == kBagDepthTopic)
      depthPub.publish(m.instantiate<sensor_msgs::Image>());
    else if (m.getTopic() == "/camera/depth/camera_info")
      infoPub.publish(m.instantiate<sensor_msgs::CameraInfo>());
    else if (m.getTopic() == "/odom")
      odomPub.publish(m.instantiate<nav_msgs::Odometry>());
    else if (m.getTopic() == "/tf")
      tfPub.publish(m.instantiate<tf2_msgs::TFMessage>());
    else if (m.getTopic() == "/tf_static")
      tfStaticPub.publish(m.instantiate<tf2_msgs::TFMessage>());
    else
      FAIL("the bag has a topic this player does not know: " << m.getTopic());
  };
  const auto playUntil = [&](const ros::Time& frames, const ros::Time& others) {
    for (; nextOther < messages.size(); ++nextOther) {
      if (isFrame(messages[nextOther])) continue;
      if (messages[nextOther].getTime() > others) break;
      publish(messages[nextOther]);
    }
    for (; nextFrame < messages.size(); ++nextFrame) {
      if (!isFrame(messages[nextFrame])) continue;
      if (messages[nextFrame].getTime() > frames) break;
      publish(messages[nextFrame]);
    }
  };
  // The mount and the camera info first (latched, as a player's first messages), given time to arrive.
  for (const auto& m : messages) {
    if (m.getTopic() == "/tf_static") tfStaticPub.publish(m.instantiate<tf2_msgs::TFMessage>());
    if (m.getTopic() == "/camera/depth/camera_info") {
      infoPub.publish(m.instantiate<sensor_msgs::CameraInfo>());
      break;
    }
  }
  std::this_thread::sleep_for(std::chrono::seconds(2));
  std::unique_ptr<sb::client::Connection> client;
  for (size_t i = 0; i < depthTimes.size(); ++i) {
    playUntil(depthTimes[i], depthTimes[i] + ros::Duration(i == 0 ? 0.0 : kLeadS));
    if (!client) {
      REQUIRE(waitForPath(socket, 30.0));
      client = std::make_unique<sb::client::Connection>(socket, 10.0);
    }
    INFO("frame " << i);
    REQUIRE(waitFor(
        [&] {
          client->send("?POLL;");
          return client->reply("POLL", 10.0).value("frames", size_t{0}) >= i + 1;
        },
        30.0));
  }
  playUntil(messages.back().getTime(), messages.back().getTime());
  client.reset();
  daemon.signal(SIGTERM);
  REQUIRE(daemon.wait(30.0) == 0);
  const auto trajectory = trajectoryLines(tmp.path + "/pushed/trajectory.tum");
  REQUIRE(trajectory.size() == static_cast<size_t>(kDriveFrames));
  const ros::Time last(lineValues(trajectory.back())[0]);
  REQUIRE(waitFor([&] { return buffer.canTransform("map", "base_link", last); }, 20.0));

  size_t checked = 0;
  double worstM = 0.0, worstRad = 0.0;
  for (size_t i = 1; i < trajectory.size(); ++i) {
    const std::vector<double> v = lineValues(trajectory[i]);
    const ros::Time stamp(v[0]);
    INFO("trajectory line " << i << ": " << trajectory[i]);
    Eigen::Isometry3d daemonPose = Eigen::Isometry3d::Identity();
    daemonPose.linear() = Eigen::Quaterniond(v[7], v[4], v[5], v[6]).normalized().toRotationMatrix();
    daemonPose.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    const Eigen::Isometry3d expected = daemonPose * mount.inverse();
    REQUIRE(buffer.canTransform("map", "base_link", stamp));
    const Eigen::Isometry3d tree = toIsometry(buffer.lookupTransform("map", "base_link", stamp).transform);
    CHECK(translationError(tree, expected) < kPositionTolM);
    CHECK(rotationError(tree, expected) < kRotationTolRad);
    worstM = std::max(worstM, translationError(tree, expected));
    worstRad = std::max(worstRad, rotationError(tree, expected));
    ++checked;
  }
  CHECK(checked == trajectory.size() - 1);
  WARN(checked << " frames of the bag: map -> base_link through tf2 against the daemon's pose with the mount: "
               << "largest " << worstM * 1e3 << " mm, " << worstRad * 1e3 << " mrad");
  for (const auto& [child, parents] : recorder.parents()) {
    INFO(child << " has parents " << parents.size() << ": " << *parents.begin() << " ...");
    CHECK(parents.size() == 1);
  }
  CHECK(recorder.edgesOf("/slambooster").count("map -> odom") == 1);
  bridge->signal(SIGINT);
  CHECK(bridge->wait(10.0) == 0);
  spinner.stop();
  ros::shutdown();
}
