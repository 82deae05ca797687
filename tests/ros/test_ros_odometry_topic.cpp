// The robot's wheel odometry from a live ROS topic (issue 41's ROS door), against a real ROS master: a
// synthetic corridor drive's depth goes over the bridge's depth topic path into the daemon's push source (as
// in test_ros_depth_topic), its odometry.txt as the base's nav_msgs/Odometry on /odom with the camera mount
// on /tf_static; slambooster_ros looks the mount up with tf2 and pushes each sample with ?ODOM. The daemon's
// trajectory equals `slambooster run` on the drive's directory (which reads odometry.txt) frame for frame within
// 0.1 mm and 1e-5 in each quaternion component, and frames.jsonl says the same frames had odometry. (Line for line
// held on most runs; one run of 2026-12-04, with the odometry's online calibration, differed by 5 um from frame 6
// on and the next by 0: the cause was not isolated; the tolerance keeps a wrong or missing odometry failing: 54 cm.) Without the odometry the comparison cannot pass: the tool
// on the same drive with --no-odometry has ATE 54 cm against 4.8 cm with it, and the bridge on another topic
// gives 118 posed frames of 120, none with odometry (tried on 2026-12-04).
//
// Pacing: the odometry is all handed over (the bridge's `slambooster: odometry in` diagnostics count it)
// after frame 0 (whose processing opens the daemon's socket; a first frame never uses odometry) and before
// frame 1, then every frame waits for the one before it, so the daemon sees what `run` sees.

#include <diagnostic_msgs/DiagnosticArray.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <signal.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <limits>
#include <map>
#include <mutex>

#include "client/connection.h"
#include "drivers/sequence.h"
#include "tests/daemon/daemon_e2e.h"
#include "tests/ros/bag_writer.h"
#include "tests/ros/ros_fixture.h"

namespace {

using namespace sb::test;
using namespace sb::test::ros_e2e;
using sb::test::e2e::kDaemon;
using sb::test::e2e::kTool;

constexpr int kDriveFrames = 120;
constexpr size_t kOdometryChunk =
    40;  // samples published before waiting for the bridge: within its queue of 100
constexpr const char* kCameraFrame = "camera_depth_optical_frame";

// frames.jsonl's frame numbers that had an odometry pose.
std::vector<int> framesWithOdometry(const std::string& path) {
  std::ifstream in(path);
  std::vector<int> frames;
  for (std::string line; std::getline(in, line);) {
    const auto j = nlohmann::json::parse(line);
    if (j.at("odometry").value("available", false)) frames.push_back(j.at("frame").get<int>());
  }
  return frames;
}

// The bridge's latest `slambooster: odometry in` counts, from /diagnostics.
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

TEST_CASE("odometry from a ROS topic reaches the daemon: the same trajectory as `slambooster run`",
          "[ros][e2e][odometry]") {
  const std::string dir = scratchDir("ros_odometry_topic");
  const std::string drive = dir + "/drive";
  const auto synth = runCommand(
      kTool + " synth --scene corridor --stress drive --seed 0 --frames " + std::to_string(kDriveFrames) +
      " --width 160 --height 120 --fx 120.3 --fy 120 --threads 1 --overwrite --out " + drive);
  INFO(synth.output);
  REQUIRE(synth.exitCode == 0);
  // 128^3 voxels of 5.9 cm at full size: depth tracks the drive, so the odometry is fused, not just followed.
  const std::string config = pipelineConfigWithHints(dir, drive, 128, "csr=1,ir=1");

  // The reference: the tool on the directory, odometry.txt beside depth.txt.
  const auto run = runCommand(kTool + " run " + drive + " --out " + dir + "/run --config " + config +
                              " --controller fixed --threads 1 --quiet 2>&1");
  INFO(run.output);
  REQUIRE(run.exitCode == 0);
  const auto expected = trajectoryLines(dir + "/run/trajectory.tum");
  REQUIRE(expected.size() == static_cast<size_t>(kDriveFrames));
  const std::vector<int> expectedOdometry = framesWithOdometry(dir + "/run/frames.jsonl");
  REQUIRE(expectedOdometry.size() >=
          static_cast<size_t>(kDriveFrames - 2));  // frame 0 and one before the first sample

  sb::SequenceOptions o;
  o.prefetch = false;
  auto source = sb::openSequence(drive, o);
  const sb::SequenceInfo info = source->info();
  std::vector<sb::DepthFrame> frames;
  while (auto f = source->next()) frames.push_back(std::move(*f));
  REQUIRE(frames.size() == static_cast<size_t>(kDriveFrames));
  std::vector<nav_msgs::Odometry> odometry = odometryMessages(drive + "/odometry.txt", /*covariance=*/false);
  REQUIRE(odometry.size() > frames.size());
  // Two hostile messages among them (issue 53): one stamped 4e9 s (it stood as the newest and every later sample
  // was refused: no odometry for the rest of the run), one between two samples with an all-zero orientation
  // (normalised to identity: a base that never turns). Each must be refused alone.
  nav_msgs::Odometry absurd = odometry[20];
  absurd.header.stamp = ros::Time(4e9);
  nav_msgs::Odometry zero = odometry[30];
  zero.header.stamp = ros::Time((odometry[30].header.stamp.toSec() + odometry[31].header.stamp.toSec()) / 2);
  zero.pose.pose.orientation = geometry_msgs::Quaternion();
  odometry.insert(odometry.begin() + 31, zero);
  odometry.insert(odometry.begin() + 21, absurd);
  constexpr size_t kHostile = 2;

  e2e::TempDir tmp;
  const std::string socket = tmp.path + "/sb.sock", push = tmp.path + "/push.sock";
  RosMaster master(tmp.path);
  joinMaster(master, "test_odometry_publisher");
  ros::NodeHandle node;
  ros::Publisher depthPub = node.advertise<sensor_msgs::Image>("/camera/depth/image", 2);
  ros::Publisher infoPub =
      node.advertise<sensor_msgs::CameraInfo>("/camera/depth/camera_info", 1, /*latch=*/true);
  ros::Publisher odomPub = node.advertise<nav_msgs::Odometry>("/odom", 1000);
  ros::Publisher tfPub = node.advertise<tf2_msgs::TFMessage>("/tf_static", 1, /*latch=*/true);
  ForwarderCounts counts;
  auto diagnostics = node.subscribe("/diagnostics", 100, &ForwarderCounts::onDiagnostics, &counts);
  ros::AsyncSpinner spinner(1);
  spinner.start();
  sensor_msgs::CameraInfo ci;
  ci.width = static_cast<uint32_t>(info.intrinsics.width);
  ci.height = static_cast<uint32_t>(info.intrinsics.height);
  ci.K = {info.intrinsics.fx, 0, info.intrinsics.cx, 0, info.intrinsics.fy, info.intrinsics.cy, 0, 0, 1};
  infoPub.publish(ci);
  tfPub.publish(cameraMountMessage(kCameraFrame, ros::Time(0.001)));

  auto bridge = startBridge(master,
                            {"socket:=" + socket, "push_socket:=" + push, "depth_topic:=/camera/depth/image",
                             "push_depth_scale:=" + std::to_string(info.depthScale), "reconnect_s:=0.05",
                             "odom_topic:=/odom", std::string("odom_camera_frame:=") + kCameraFrame},
                            tmp.path + "/bridge.log");
  INFO(bridge->log());
  REQUIRE(waitFor(
      [&] {
        return depthPub.getNumSubscribers() >= 1 && infoPub.getNumSubscribers() >= 1 &&
               odomPub.getNumSubscribers() >= 1 && tfPub.getNumSubscribers() >= 1 &&
               diagnostics.getNumPublishers() >= 1;
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
    // After frame 0 (the daemon's socket is open): every odometry sample, in chunks the bridge's queue holds.
    for (size_t k = 0; k < odometry.size(); ++k) {
      odomPub.publish(odometry[k]);
      if ((k + 1) % kOdometryChunk != 0 && k + 1 != odometry.size()) continue;
      INFO("odometry samples published: " << k + 1);
      REQUIRE(waitFor(
          [&] {
            return counts.get("pushed") + counts.get("skipped_no_mount") + counts.get("failed") >= k + 1;
          },
          20.0));
    }
    CHECK(counts.get("skipped_no_mount") == 0);
    CHECK(counts.get("failed") == kHostile);
    REQUIRE(counts.get("pushed") == odometry.size() - kHostile);
  }
  client->send("?STATUS;");
  const auto status = client->reply("STATUS", 10.0);
  INFO(status.dump());
  CHECK(status.value("drops", -1) == 0);
  CHECK(status["odometry"].value("frames", size_t{0}) == expectedOdometry.size());

  client.reset();
  daemon.signal(SIGTERM);
  REQUIRE(daemon.wait(30.0) == 0);
  CHECK(framesWithOdometry(tmp.path + "/pushed/frames.jsonl") == expectedOdometry);
  const auto got = trajectoryLines(tmp.path + "/pushed/trajectory.tum");
  REQUIRE(got.size() == expected.size());
  double worst = 0.0;
  for (size_t i = 0; i < expected.size(); ++i) {
    INFO("frame " << i << ": " << got[i] << " against " << expected[i]);
    std::istringstream a(got[i]), b(expected[i]);
    std::vector<double> x(8), y(8);
    for (int k = 0; k < 8; ++k) a >> x[k], b >> y[k];
    REQUIRE((a && b));
    CHECK(x[0] == y[0]);  // the same stamp
    for (int k = 1; k < 4; ++k) CHECK(std::abs(x[k] - y[k]) < 1e-4);
    for (int k = 4; k < 8; ++k) CHECK(std::abs(x[k] - y[k]) < 1e-5);
    for (int k = 1; k < 4; ++k) worst = std::max(worst, std::abs(x[k] - y[k]));
  }
  WARN("largest position difference to `slambooster run`: " << worst << " m");
  bridge->signal(SIGINT);
  CHECK(bridge->wait(10.0) == 0);
  spinner.stop();
  ros::shutdown();
}
