// slamboosterd on a live OpenNI2 camera (the test camera driver): the camera is unplugged mid-run; the daemon
// keeps serving the socket, STATUS shows the source lost, then streaming again after the reconnect.

#include <signal.h>
#include <stdlib.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <optional>
#include <nlohmann/json.hpp>
#include <thread>

#include "tests/daemon/process.h"
#include "tests/support/run_command.h"

using nlohmann::json;
using sb::test::runCommand;

namespace {

const std::string kDaemon = SB_SLAMBOOSTERD_BIN;
const std::string kCtl = SB_SLAMBOOSTERCTL_BIN;

struct TempDir {
  std::string path;
  TempDir() {
    char t[] = "/tmp/sbd-oni-XXXXXX";
    if (!mkdtemp(t)) throw std::runtime_error("mkdtemp");
    path = t;
  }
  ~TempDir() { std::filesystem::remove_all(path); }
};

std::optional<json> daemonStatus(const std::string& socket) {
  const auto r = runCommand(kCtl + " --json --socket " + socket + " status");
  if (r.exitCode != 0) return std::nullopt;
  return json::parse(r.output.substr(0, r.output.find('\n')), nullptr, false);
}

}  // namespace

TEST_CASE("slamboosterd on an OpenNI2 camera: unplugged mid-run, STATUS shows it lost, then reconnected",
          "[openni2][daemon]") {
  TempDir tmp;
  const std::string socket = tmp.path + "/s.sock", pipeline = tmp.path + "/pipeline.json";
  std::ofstream(pipeline) << R"({"volume_resolution": 64, "knobs": "csr=4,ir=1"})";
  const std::string uri = "sbtest://cam?disconnect_after=45&unplugged_ms=1500";
  sb::test::ChildProcess d({kDaemon, "--out", tmp.path + "/out", "--socket", socket, "--controller", "fixed",
                            "--cpus", "all", "--set", "source.type=openni2", "--set", "source.camera.uri=" + uri,
                            "--set", "source.camera.width=320", "--set", "source.camera.height=240", "--set",
                            "source.camera.reconnect_min_s=0.1", "--set", "source.camera.reconnect_max_s=0.4",
                            "--set", "slam.pipeline_config=" + pipeline, "--set", "slam.threads=1"},
                           {std::string("LD_LIBRARY_PATH=") + SB_OPENNI2_RUNTIME}, tmp.path + "/log.txt");
  REQUIRE(sb::test::waitForPath(socket, 20));

  // 45 frames at 30 fps, then 1.5 s unplugged: poll STATUS every 50 ms for up to 15 s.
  bool sawStreaming = false, sawLost = false, sawBack = false;
  uint64_t framesWhenLost = 0, framesAtEnd = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(15);
  while (std::chrono::steady_clock::now() < deadline && !(sawBack && framesAtEnd > framesWhenLost + 10)) {
    const auto s = daemonStatus(socket);
    INFO(d.log());
    REQUIRE(s);  // the socket is served throughout
    REQUIRE(s->contains("source"));
    const json& src = (*s)["source"];
    CHECK(src["type"] == "openni2");
    CHECK(src["live"] == true);
    const std::string state = src["state"];
    if (state == "streaming" && !sawLost) sawStreaming = true;
    if (state == "lost" && !sawLost) {
      sawLost = true;
      framesWhenLost = src["frames"];
      CHECK_THAT(src.value("source_error", std::string()), Catch::Contains("disconnected"));
      CHECK(src["disconnects"] == 1);
    }
    if (sawLost && state == "streaming") {
      sawBack = true;
      framesAtEnd = src["frames"];
      CHECK(src["reconnects"] == 1);
      CHECK(src["mode"] == "320x240@30 1mm");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  INFO(d.log());
  CHECK(sawStreaming);
  CHECK(sawLost);
  CHECK(sawBack);
  CHECK(framesWhenLost <= 45);  // the driver sends 45 frames; a slow capture thread may miss one
  CHECK(framesWhenLost >= 40);
  CHECK(framesAtEnd > framesWhenLost + 10);  // frames flow again after the reconnect

  d.signal(SIGTERM);
  CHECK(d.wait(20) == 0);
  // A live camera's outputs rotate (output.rotation mode live): trajectory-000001.tum, ...
  bool trajectory = false;
  for (const auto& e : std::filesystem::directory_iterator(tmp.path + "/out"))
    trajectory = trajectory || e.path().filename().string().rfind("trajectory", 0) == 0;
  CHECK(trajectory);
}

TEST_CASE("slamboosterd: an OpenNI2 source with replay keys is a configuration error (exit 2)",
          "[openni2][daemon]") {
  TempDir tmp;
  sb::test::ChildProcess d({kDaemon, "--out", tmp.path + "/out", "--socket", tmp.path + "/s.sock", "--set",
                            "source.type=openni2", "--input", "/some/sequence"},
                           {std::string("LD_LIBRARY_PATH=") + SB_OPENNI2_RUNTIME}, tmp.path + "/log.txt");
  CHECK(d.wait(20) == 2);
  CHECK_THAT(d.log(), Catch::Contains("source.camera.uri"));
}
