// Depth from ROS topics into slamboosterd: this program publishes the synthetic sequence's frames as
// sensor_msgs/Image (32FC1 metres) + CameraInfo, slambooster_ros forwards them to the daemon's push source,
// and the daemon's trajectory equals its replay of the same frames bit for bit (frames are paced by the
// daemon's progress, so none is dropped, and STATUS says so). Then frames stamped with the wall clock at
// 30 Hz measure the latency the path adds (ROS publish -> frame in the daemon's hands).

#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <signal.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "client/connection.h"
#include "drivers/sequence.h"
#include "tests/daemon/daemon_e2e.h"
#include "tests/ros/ros_fixture.h"

namespace {

using namespace sb::test;
using namespace sb::test::ros_e2e;
using sb::test::e2e::fixture;
using sb::test::e2e::kDaemon;

constexpr double kFramePeriodS = 1.0 / 30.0;

struct Frames {
  sb::SequenceInfo info;
  std::vector<sb::DepthFrame> frames;
};

Frames readSequence(const std::string& path) {
  sb::SequenceOptions o;
  o.prefetch = false;
  auto source = sb::openSequence(path, o);
  Frames f{source->info(), {}};
  while (auto frame = source->next()) f.frames.push_back(std::move(*frame));
  return f;
}

nlohmann::json request(sb::client::Connection& c, const std::string& line, const std::string& cls) {
  c.send(line);
  return c.reply(cls, 10.0);
}

TEST_CASE("depth from a ROS topic reaches the daemon: same trajectory as the replay, latency measured",
          "[ros][e2e]") {
  const auto& seq = fixture();
  const Frames frames = readSequence(seq.sequence);
  REQUIRE(frames.frames.size() == static_cast<size_t>(e2e::kFrames));
  e2e::TempDir tmp;
  const std::string socket = tmp.path + "/sb.sock", push = tmp.path + "/push.sock";
  const std::string config = pipelineConfigWithHints(tmp.path, seq.sequence);  // pushed frames carry no hints

  // The reference: the daemon replaying the same frames.
  const std::string replayOut = tmp.path + "/replay";
  {
    auto args = withPipelineConfig(e2e::daemonArgs(tmp.path + "/replay.sock", replayOut, "fast", "exit"), config);
    ChildProcess replay(args, {}, tmp.path + "/replay.log");
    const int code = replay.wait(120.0);
    INFO(replay.log());
    REQUIRE(code == 0);
  }
  const auto expected = trajectoryLines(replayOut + "/trajectory.tum");
  REQUIRE(expected.size() == frames.frames.size());

  RosMaster master(tmp.path);
  joinMaster(master, "test_depth_publisher");
  ros::NodeHandle node;
  ros::Publisher depthPub = node.advertise<sensor_msgs::Image>("/camera/depth/image", 2);
  ros::Publisher infoPub = node.advertise<sensor_msgs::CameraInfo>("/camera/depth/camera_info", 1, /*latch=*/true);
  sensor_msgs::CameraInfo ci;
  ci.width = static_cast<uint32_t>(frames.info.intrinsics.width);
  ci.height = static_cast<uint32_t>(frames.info.intrinsics.height);
  ci.K = {frames.info.intrinsics.fx, 0, frames.info.intrinsics.cx, 0, frames.info.intrinsics.fy,
          frames.info.intrinsics.cy, 0, 0, 1};
  infoPub.publish(ci);

  auto bridge = startBridge(master,
                            {"socket:=" + socket, "push_socket:=" + push, "depth_topic:=/camera/depth/image",
                             "push_depth_scale:=" + std::to_string(frames.info.depthScale), "reconnect_s:=0.05"},
                            tmp.path + "/bridge.log");
  INFO(bridge->log());
  REQUIRE(waitFor([&] { return depthPub.getNumSubscribers() >= 1 && infoPub.getNumSubscribers() >= 1; }, 20.0));

  auto daemonArgs = withPipelineConfig(e2e::daemonArgs(socket, tmp.path + "/pushed", "recorded", "stop"), config);
  daemonArgs[2] = push;  // --input: the push source's socket
  // A push source is live, so its outputs would rotate (frames-000001.jsonl, ...): single files here, to compare
  // trajectory.tum with the replay's line for line.
  daemonArgs.insert(daemonArgs.end(), {"--set", "source.type=push", "--set", "output.rotation.mode=never"});
  ChildProcess daemon(daemonArgs, {}, tmp.path + "/daemon.log");
  INFO(daemon.log());
  // The push source waits for the first frame (it sizes the pipeline); the daemon's socket appears after it.
  REQUIRE(waitFor([&] { return waitForPath(push, 0.01); }, 30.0));
  std::unique_ptr<sb::client::Connection> client;
  for (size_t i = 0; i < frames.frames.size(); ++i) {
    const auto& f = frames.frames[i];
    depthPub.publish(depthImage(f, frames.info.depthScale, ros::Time(f.timestamp)));
    if (!client) {
      REQUIRE(waitForPath(socket, 30.0));
      client = std::make_unique<sb::client::Connection>(socket, 10.0);
    }
    // Paced by the daemon: the next frame only once this one was processed (no drops by construction).
    INFO("frame " << i);
    REQUIRE(waitFor([&] { return request(*client, "?POLL;", "POLL").value("frames", size_t{0}) >= i + 1; }, 30.0));
  }
  const auto status = request(*client, "?STATUS;", "STATUS");
  INFO(status.dump());
  CHECK(status.value("drops", -1) == 0);
  CHECK(status["source"].value("type", "") == "push");
  CHECK(status["source"].value("rejected", -1) == 0);

  // Latency: frames stamped with the wall clock (as a live camera driver stamps them) at 30 Hz; the push
  // source records, per frame, wall clock on arrival minus the stamp.
  std::vector<double> agesMs;
  for (size_t i = 0; i < frames.frames.size(); ++i) {
    depthPub.publish(depthImage(frames.frames[i], frames.info.depthScale, ros::Time::now()));
    std::this_thread::sleep_for(std::chrono::duration<double>(kFramePeriodS));
    agesMs.push_back(request(*client, "?STATUS;", "STATUS")["source"].value("last_arrival_age_ms", -1.0));
  }
  std::sort(agesMs.begin(), agesMs.end());
  const double median = agesMs[agesMs.size() / 2];
  WARN("ROS topic -> daemon push source latency over " << agesMs.size() << " frames at 30 Hz: median " << median
                                                          << " ms, max " << agesMs.back() << " ms");
  CHECK(median >= 0.0);
  CHECK(median < kFramePeriodS * 1e3);  // it must keep up with a 30 Hz camera

  client.reset();
  daemon.signal(SIGTERM);
  REQUIRE(daemon.wait(30.0) == 0);
  const auto got = trajectoryLines(tmp.path + "/pushed/trajectory.tum");
  REQUIRE(got.size() >= expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    INFO("frame " << i);
    CHECK(got[i] == expected[i]);
  }
  bridge->signal(SIGINT);
  CHECK(bridge->wait(10.0) == 0);
  ros::shutdown();
}

}  // namespace
