// slambooster_ros end to end against a real ROS master: the daemon replays the short synthetic sequence, the
// bridge publishes, this program subscribes. One Odometry per frame in order with the daemon's poses (the
// values of trajectory.tum), the configured frame ids, the frames' timestamps as stamps, a covariance that
// follows the tracking state, a TF that resolves, diagnostics; then the daemon is killed and restarted and
// the stream resumes through the same bridge.

#include <diagnostic_msgs/DiagnosticArray.h>
#include <nav_msgs/Odometry.h>
#include <signal.h>
#include <std_msgs/String.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <cmath>
#include <mutex>

#include "tests/daemon/daemon_e2e.h"
#include "tests/ros/ros_fixture.h"

namespace {

using namespace sb::test;
using namespace sb::test::ros_e2e;
using sb::test::e2e::fixture;

constexpr const char* kMapFrame = "test_map";
constexpr const char* kCameraFrame = "test_camera";
// Frames the daemon may publish before the bridge, polling every 50 ms, has connected (a client sees only
// what is published after it connects: the protocol has no history).
constexpr size_t kMaxMissedAtStart = 5;
constexpr double kGoodSigmaM = 0.01;  // the bridge's default ~sigma_good_position_m
constexpr double kLostSigmaM = 1000.0;
constexpr double kWeakAxisSigma = 1.0;  // ~sigma_weak_axis_*

struct Received {
  std::mutex mutex;
  std::vector<nav_msgs::Odometry> odometry;
  std::vector<std::string> states;
  std::vector<diagnostic_msgs::DiagnosticStatus> diagnostics;
  size_t odometryCount() {
    std::lock_guard lock(mutex);
    return odometry.size();
  }
};

// The tracking state per frame from the daemon's frames.jsonl: its `state` when it writes one, otherwise
// derived as the bridge derives it from POSE (not tracked: lost; not constrained: weak).
std::vector<std::string> frameStates(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> states;
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) {
      const auto j = nlohmann::json::parse(line);
      if (j.contains("state") && j["state"].is_string())
        states.push_back(j["state"]);
      else
        states.push_back(!j.at("tracked").get<bool>() ? "lost" : !j.value("constrained", true) ? "weak" : "good");
    }
  return states;
}

// Checks the messages `from`.. against the trajectory of one daemon run: each matches a trajectory line by
// stamp, in order without gaps up to the last frame, starting at most kMaxMissedAtStart frames late.
void checkRun(Received& r, size_t from, const std::string& outDir) {
  const auto lines = trajectoryLines(outDir + "/trajectory.tum");
  const auto states = frameStates(outDir + "/frames.jsonl");
  REQUIRE(lines.size() == static_cast<size_t>(sb::test::e2e::kFrames));
  REQUIRE(states.size() == lines.size());
  std::lock_guard lock(r.mutex);
  REQUIRE(r.odometry.size() > from);
  const size_t count = r.odometry.size() - from;
  REQUIRE(count + kMaxMissedAtStart >= lines.size());
  REQUIRE(count <= lines.size());
  const size_t first = lines.size() - count;
  for (size_t i = 0; i < count; ++i) {
    const auto& m = r.odometry[from + i];
    const auto v = lineValues(lines[first + i]);
    INFO("frame " << first + i << ": " << lines[first + i]);
    CHECK(m.header.frame_id == kMapFrame);
    CHECK(m.child_frame_id == kCameraFrame);
    char stamp[32];
    std::snprintf(stamp, sizeof stamp, "%.6f", m.header.stamp.toSec());
    CHECK(lines[first + i].substr(0, lines[first + i].find(' ')) == stamp);
    const auto& p = m.pose.pose.position;
    const auto& q = m.pose.pose.orientation;
    const double values[] = {p.x, p.y, p.z, q.x, q.y, q.z, q.w};
    for (int k = 0; k < 7; ++k) CHECK(std::abs(values[k] - v[k + 1]) <= 1e-9);  // trajectory.tum has 9 decimals
    // The covariance follows the state: certain where good, uncertain along something where weak, not at
    // all where lost.
    double trace = 0;
    for (int k = 0; k < 6; ++k) trace += m.pose.covariance[static_cast<size_t>(k * 7)];
    const std::string& state = states[first + i];
    INFO("state " << state << ", covariance trace " << trace);
    if (state == "good") CHECK(trace <= 6 * kGoodSigmaM * kGoodSigmaM * 1.0001);
    if (state == "weak") CHECK(trace >= kWeakAxisSigma * kWeakAxisSigma * 0.999);
    if (state == "lost") CHECK(trace >= kLostSigmaM * kLostSigmaM * 0.999);
  }
}

TEST_CASE("slambooster_ros publishes the daemon's poses and survives a daemon restart", "[ros][e2e]") {
  fixture();  // the short synthetic sequence, made once (daemonArgs replays it)
  e2e::TempDir tmp;
  const std::string socket = tmp.path + "/sb.sock";
  RosMaster master(tmp.path);
  joinMaster(master, "test_bridge_subscriber");
  ros::NodeHandle node;

  Received r;
  auto odomSub = node.subscribe<nav_msgs::Odometry>("/slambooster/odometry", 1000,
                                                    [&](const nav_msgs::Odometry::ConstPtr& m) {
                                                      std::lock_guard lock(r.mutex);
                                                      r.odometry.push_back(*m);
                                                    });
  auto stateSub = node.subscribe<std_msgs::String>("/slambooster/tracking_state", 1000,
                                                   [&](const std_msgs::String::ConstPtr& m) {
                                                     std::lock_guard lock(r.mutex);
                                                     r.states.push_back(m->data);
                                                   });
  auto diagSub = node.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 1000, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
        std::lock_guard lock(r.mutex);
        for (const auto& s : m->status) r.diagnostics.push_back(s);
      });
  tf2_ros::Buffer tfBuffer(ros::Duration(60.0));
  tf2_ros::TransformListener tfListener(tfBuffer);
  ros::AsyncSpinner spinner(2);
  spinner.start();

  auto bridge = startBridge(master,
                            {"socket:=" + socket, std::string("map_frame:=") + kMapFrame,
                             std::string("camera_frame:=") + kCameraFrame, "reconnect_s:=0.05"},
                            tmp.path + "/bridge.log");
  INFO(bridge->log());
  REQUIRE(waitFor([&] { return odomSub.getNumPublishers() >= 1 && diagSub.getNumPublishers() >= 1; }, 20.0));

  const std::string out1 = tmp.path + "/run1";
  {
    ChildProcess daemon(e2e::daemonArgs(socket, out1, "recorded", "stop"), {}, tmp.path + "/daemon1.log");
    INFO(daemon.log());
    REQUIRE(waitFor([&] { return r.odometryCount() >= 1; }, 30.0));
    // The last frame's Odometry, then every output of the run is on disk (the worker flushes at the end).
    REQUIRE(waitFor([&] { return trajectoryLines(out1 + "/trajectory.tum").size() == 30 &&
                                 r.odometryCount() + kMaxMissedAtStart >= 30; }, 60.0));
    REQUIRE(waitFor([&] {
      std::lock_guard lock(r.mutex);
      return !r.odometry.empty() && std::abs(r.odometry.back().header.stamp.toSec() -
                                             lineValues(trajectoryLines(out1 + "/trajectory.tum").back())[0]) < 1e-6;
    }, 10.0));
    checkRun(r, 0, out1);

    // The TF of the last frame resolves to the same pose.
    nav_msgs::Odometry last;
    {
      std::lock_guard lock(r.mutex);
      last = r.odometry.back();
    }
    REQUIRE(tfBuffer.canTransform(kMapFrame, kCameraFrame, last.header.stamp, ros::Duration(5.0)));
    const auto t = tfBuffer.lookupTransform(kMapFrame, kCameraFrame, last.header.stamp);
    CHECK(t.transform.translation.x == last.pose.pose.position.x);
    CHECK(t.transform.translation.y == last.pose.pose.position.y);
    CHECK(t.transform.translation.z == last.pose.pose.position.z);
    CHECK(t.transform.rotation.w == last.pose.pose.orientation.w);

    // Diagnostics carry the state, knobs and computation time per frame.
    std::lock_guard lock(r.mutex);
    REQUIRE(!r.diagnostics.empty());
    const auto& d = r.diagnostics.back();
    CHECK(d.name == "slambooster: tracking");
    std::set<std::string> keys;
    for (const auto& kv : d.values) keys.insert(kv.key);
    for (const char* k : {"frame", "state", "controller", "csr", "icp", "pd", "tr", "ir", "computation_ms"})
      CHECK(keys.count(k) == 1);
    CHECK(!r.states.empty());
    daemon.signal(SIGKILL);  // a crash: the socket file stays behind, the bridge sees the connection drop
    daemon.wait(10.0);
  }

  const size_t before = r.odometryCount();
  REQUIRE(waitFor([&] {
    std::lock_guard lock(r.mutex);
    return !r.states.empty() && r.states.back() == "disconnected";
  }, 10.0));
  const std::string out2 = tmp.path + "/run2";
  ChildProcess daemon2(e2e::daemonArgs(socket, out2, "recorded", "stop"), {}, tmp.path + "/daemon2.log");
  INFO(daemon2.log());
  REQUIRE(waitFor([&] { return trajectoryLines(out2 + "/trajectory.tum").size() == 30; }, 60.0));
  REQUIRE(waitFor([&] {
    std::lock_guard lock(r.mutex);
    return r.odometry.size() > before &&
           std::abs(r.odometry.back().header.stamp.toSec() -
                    lineValues(trajectoryLines(out2 + "/trajectory.tum").back())[0]) < 1e-6;
  }, 10.0));
  checkRun(r, before, out2);
  daemon2.signal(SIGTERM);
  CHECK(daemon2.wait(20.0) == 0);
  bridge->signal(SIGINT);
  CHECK(bridge->wait(10.0) == 0);
  spinner.stop();
  ros::shutdown();
}

}  // namespace
