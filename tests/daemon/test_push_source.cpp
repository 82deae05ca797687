// The daemon's push source attacked (issue 44): silent and half-sent clients never keep SIGTERM from ending
// the daemon (P1), a silent pusher mid-run is named and closed after source.push_timeout_s, whether or not
// another waits, a pusher that closed before it was accepted is not processed (P5), tiny, absurd or huge
// frames are refused and the daemon keeps serving (P6, P7), stamps that trajectory.tum could not keep are
// refused (P8), the push socket follows socket.mode (P2), and the configuration checks of P9 and S5. Real
// processes and sockets; frames of the fixture's sequence pushed with the client library
// (client/frame_pusher.h).

#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

#include "client/frame_pusher.h"
#include "core/trajectory.h"
#include "core/unique_fd.h"
#include "drivers/sequence.h"
#include "tests/daemon/daemon_e2e.h"
#include "tests/daemon/process.h"
#include "tests/support/files.h"

using namespace sb::test::e2e;
using sb::test::ChildProcess;
using Clock = std::chrono::steady_clock;

namespace {

struct Frames {
  std::vector<sb::DepthRaw> depth;
  sb::PushedFrameHeader header;  // the sequence's camera; stamp and size set per frame
};

const Frames& frames() {
  static const Frames f = [] {
    Frames out;
    auto source = sb::openSequence(fixture().sequence);
    const sb::Intrinsics& k = source->info().intrinsics;
    out.header.fx = k.fx;
    out.header.fy = k.fy;
    out.header.cx = k.cx;
    out.header.cy = k.cy;
    out.header.depthScale = source->info().depthScale;
    while (auto frame = source->next()) out.depth.push_back(frame->depth);
    return out;
  }();
  return f;
}

void push(sb::client::FramePusher& pusher, size_t i, double stamp) {
  sb::PushedFrameHeader h = frames().header;
  h.timestamp = stamp;
  pusher.push(h, frames().depth[i % frames().depth.size()]);
}

// A raw connection to the push socket, for clients that misbehave.
sb::UniqueFd connectRaw(const std::string& path) {
  sb::UniqueFd fd(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::snprintf(addr.sun_path, sizeof addr.sun_path, "%s", path.c_str());
  REQUIRE(::connect(fd.get(), reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0);
  return fd;
}

struct PushDaemon {
  TempDir tmp;
  std::string socket, pushPath, out;
  std::unique_ptr<ChildProcess> process;
  explicit PushDaemon(const std::string& name, const std::vector<std::string>& extra = {}) {
    socket = tmp.path + "/s.sock";
    pushPath = tmp.path + "/push.sock";
    out = sb::test::scratchDir("push_source_" + name) + "/out";
    std::vector<std::string> args = {kDaemon,
                                     "--input",
                                     pushPath,
                                     "--out",
                                     out,
                                     "--socket",
                                     socket,
                                     "--set",
                                     "source.type=push",
                                     "--set",
                                     "output.rotation.mode=never",
                                     "--set",
                                     "slam.pipeline_config=" + fixture().pipelineConfig,
                                     "--controller",
                                     "fixed"};
    args.insert(args.end(), extra.begin(), extra.end());
    process = std::make_unique<ChildProcess>(args, std::vector<std::string>{}, out + "-log.txt");
    REQUIRE(sb::test::waitForPath(pushPath, 20));
  }
  // SIGTERM, and the seconds until the daemon exited (its status in `status`).
  double terminate(int& status) {
    const auto start = Clock::now();
    process->signal(SIGTERM);
    status = process->wait(10);
    return std::chrono::duration<double>(Clock::now() - start).count();
  }
  bool logSays(const std::string& text) const { return process->log().find(text) != std::string::npos; }
  bool waitLog(const std::string& text, double seconds) const {
    const auto deadline = Clock::now() + std::chrono::duration<double>(seconds);
    while (Clock::now() < deadline && !logSays(text)) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    return logSays(text);
  }
  nlohmann::json status() const { return ctlJson(socket, "status"); }
  // Waits until trajectory.tum has `lines` frames (the SLAM thread took them).
  bool waitTracked(size_t lines, double seconds) const {
    const auto deadline = Clock::now() + std::chrono::duration<double>(seconds);
    while (Clock::now() < deadline && dataLines(out + "/trajectory.tum") < lines)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    return dataLines(out + "/trajectory.tum") >= lines;
  }
  size_t framesDone() const { return status()["source"].value("frames", size_t(0)); }
  // Waits for the control socket (the daemon makes it at the first frame), then up to 10 s until the source
  // took `frames` frames; STATUS's "source" object.
  nlohmann::json sourceAfter(size_t frames) const {
    REQUIRE(sb::test::waitForPath(socket, 20));
    const auto deadline = Clock::now() + std::chrono::seconds(10);
    while (Clock::now() < deadline && framesDone() < frames) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    return status()["source"];
  }
};

void writeAll(int fd, const void* data, size_t bytes) { REQUIRE(::send(fd, data, bytes, MSG_NOSIGNAL) == ssize_t(bytes)); }

}  // namespace

TEST_CASE("push source: SIGTERM ends the daemon within 2 s in every state of the source", "[daemon][push][system]") {
  const auto header = [](double stamp) {
    sb::PushedFrameHeader h = frames().header;
    h.width = 320;
    h.height = 240;
    h.timestamp = stamp;
    return sb::encodePushedHeader(h);
  };
  for (const std::string state : {"no client", "silent before the first frame", "half a header first",
                                  "silent mid-run", "half a payload mid-run"}) {
    INFO(state);
    PushDaemon d("sigterm");
    sb::UniqueFd raw;
    std::unique_ptr<sb::client::FramePusher> pusher;
    if (state == "silent before the first frame") raw = connectRaw(d.pushPath);
    if (state == "half a header first") {
      raw = connectRaw(d.pushPath);
      writeAll(raw.get(), header(1.0).data(), 20);
    }
    if (state == "silent mid-run" || state == "half a payload mid-run") {
      pusher = std::make_unique<sb::client::FramePusher>(d.pushPath);
      for (size_t i = 0; i < 3; ++i) push(*pusher, i, 1.0 + i * 0.033);
      REQUIRE(sb::test::waitForPath(d.socket, 20));
      if (state == "half a payload mid-run") {
        raw = connectRaw(d.pushPath);  // waits behind the pusher
        pusher.reset();                // the pusher goes; the raw client is accepted and sends half a frame
        const auto h = header(2.0);
        writeAll(raw.get(), h.data(), h.size());
        writeAll(raw.get(), frames().depth[0].data(), 1000);
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    int status = 0;
    const double seconds = d.terminate(status);
    INFO(d.process->log());
    CHECK(status != -2);
    CHECK(seconds < 2.0);
  }
}

TEST_CASE("push source: a silent pusher is named and gives way to a waiting one; a closed one's frames are stale",
          "[daemon][push][system]") {
  PushDaemon d("silent");
  {
    sb::client::FramePusher first(d.pushPath);
    for (size_t i = 0; i < 3; ++i) push(first, i, 1.0 + i * 0.033);
    REQUIRE(sb::test::waitForPath(d.socket, 20));
    // A pusher that sends one frame and closes while `first` holds the source: stale when accepted.
    {
      sb::client::FramePusher gone(d.pushPath);
      push(gone, 3, 50.0);
    }
    sb::client::FramePusher waiting(d.pushPath);  // waits behind `first`, which now says nothing
    REQUIRE(d.waitLog("has sent nothing for", 10));
    CHECK(d.logSays("uid"));  // named: pid, program, uid
    CHECK(d.logSays("had already closed its connection when it was accepted"));
    push(waiting, 4, 2.0);
    push(waiting, 5, 2.033);
    CHECK(d.sourceAfter(5)["frames"] == 5);  // 3 of `first`, 2 of `waiting`; none of `gone`
  }
  int status = 0;
  d.terminate(status);
  CHECK(status == 0);
  const auto stamps = trajectoryTimestamps(d.out + "/trajectory.tum");
  CHECK(stamps.count("50.000000") == 0);
}

TEST_CASE("push source: a pusher silent between frames is closed after source.push_timeout_s on its own",
          "[daemon][push][system]") {
  // No other pusher waits: the silent one is named and closed by its own timeout, its end of the socket sees
  // the close, and the next pusher is served (before, it held the source until another waited). With the
  // default timeout (5 s) and a configured one (1 s).
  const auto silentAlone = [](const std::vector<std::string>& extra, double timeout) {
    PushDaemon d("silent_alone", extra);
    sb::UniqueFd held = connectRaw(d.pushPath);
    for (size_t i = 0; i < 3; ++i) {
      sb::PushedFrameHeader h = frames().header;
      h.width = uint32_t(frames().depth[i].width());
      h.height = uint32_t(frames().depth[i].height());
      h.timestamp = 1.0 + i * 0.033;
      const auto head = sb::encodePushedHeader(h);
      writeAll(held.get(), head.data(), head.size());
      writeAll(held.get(), frames().depth[i].data(), frames().depth[i].size() * sizeof(uint16_t));
    }
    const auto sent = Clock::now();
    REQUIRE(sb::test::waitForPath(d.socket, 20));
    // The daemon's end closes: recv on the held socket returns 0 (end of stream).
    bool closed = false;
    while (!closed && Clock::now() < sent + std::chrono::duration<double>(timeout + 10)) {
      pollfd p{held.get(), POLLIN, 0};
      char byte;
      if (::poll(&p, 1, 50) == 1) closed = ::recv(held.get(), &byte, 1, 0) == 0;
    }
    const double after = std::chrono::duration<double>(Clock::now() - sent).count();
    INFO("timeout " << timeout << " s, closed after " << after << " s\n" << d.process->log());
    CHECK(closed);
    CHECK(after >= timeout - 0.1);  // not before source.push_timeout_s
    CHECK(after < timeout + 5);  // the timeout and a loaded machine's slack, not "until another pusher waits"
    CHECK(d.logSays("between frames (source.push_timeout_s): closing it"));
    CHECK(d.logSays("uid"));  // named: pid, program, uid
    CHECK(d.status()["source"]["state"] == "waiting");
    if (closed) {  // else the next pusher's first frame would block behind the held socket
      sb::client::FramePusher next(d.pushPath);
      push(next, 3, 2.0);
      push(next, 4, 2.033);
      const auto deadline = Clock::now() + std::chrono::seconds(10);
      while (Clock::now() < deadline && d.framesDone() < 5)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      CHECK(d.framesDone() == 5);
    }
    int status = 0;
    d.terminate(status);
    CHECK(status == 0);
  };
  silentAlone({}, 5.0);
  silentAlone({"--set", "source.push_timeout_s=1"}, 1.0);
}

TEST_CASE("push source: a pusher that pauses past source.push_timeout_s goes on with the next frame",
          "[daemon][push][system]") {
  // The daemon closes the paused pusher; the client library connects again before its next frame, so no
  // frame is lost to the closed connection (client/frame_pusher.h).
  PushDaemon d("pause", {"--set", "source.push_timeout_s=1"});
  sb::client::FramePusher pusher(d.pushPath);
  for (size_t i = 0; i < 3; ++i) push(pusher, i, 1.0 + i * 0.033);
  REQUIRE(sb::test::waitForPath(d.socket, 20));
  REQUIRE(d.waitLog("(silent); waiting for another", 10));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the close has reached the client's end
  CHECK_NOTHROW(push(pusher, 3, 2.0));
  CHECK_NOTHROW(push(pusher, 4, 2.033));
  const auto deadline = Clock::now() + std::chrono::seconds(10);
  while (Clock::now() < deadline && d.framesDone() < 5)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  CHECK(d.framesDone() == 5);
  CHECK(d.status()["source"]["connections"] == 2);
  int status = 0;
  d.terminate(status);
  CHECK(status == 0);
}

TEST_CASE("push source: tiny, absurd and huge first frames are refused, the daemon keeps serving",
          "[daemon][push][system]") {
  // With the default source.max_frame_pixels (1280x1024); the next case sets it.
  PushDaemon d("bounds");
  sb::client::FramePusher pusher(d.pushPath);
  const auto pushWith = [&](const std::function<void(sb::PushedFrameHeader&)>& change, int w, int h) {
    sb::PushedFrameHeader header = frames().header;
    header.timestamp = 1.0;
    change(header);
    pusher.push(header, sb::DepthRaw(w, h, 1000));
  };
  const float inf = std::numeric_limits<float>::infinity();
  pushWith([](sb::PushedFrameHeader&) {}, 1, 1);                           // P6
  pushWith([](sb::PushedFrameHeader&) {}, 2, 2);                           // P6
  pushWith([&](sb::PushedFrameHeader& h) { h.fx = inf; }, 320, 240);       // P7
  pushWith([](sb::PushedFrameHeader& h) { h.fy = 1e-30f; }, 320, 240);     // P7
  pushWith([](sb::PushedFrameHeader& h) { h.cx = 1e30f; }, 320, 240);      // P7
  pushWith([](sb::PushedFrameHeader& h) { h.depthScale = 1e-300; }, 320, 240);  // P7
  pushWith([](sb::PushedFrameHeader&) {}, 1600, 1200);  // P7: over source.max_frame_pixels
  REQUIRE(d.waitLog("width x height = 1.92e+06 pixels is not plausible", 10));
  for (const char* said :
       {"width = 1 pixels is not plausible", "width = 2 pixels is not plausible",
        "fx = inf pixels is not plausible", "fy = 1e-30 pixels is not plausible",
        "cx = 1e+30 pixels is not plausible", "depth_scale = 1e-300 raw units per metre is not plausible"}) {
    INFO(said);
    CHECK(d.logSays(said));
  }
  // The daemon still waits for a first frame, and takes a good one.
  for (size_t i = 0; i < 3; ++i) push(pusher, i, 2.0 + i * 0.033);
  const nlohmann::json s = d.sourceAfter(3);
  CHECK(s["frames"] == 3);
  CHECK(s["rejected"] == 7);
  CHECK(d.waitTracked(3, 20));
  int status = 0;
  d.terminate(status);
  CHECK(status == 0);
  CHECK(sb::test::readJson(d.out + "/summary.json")["frames"] == 3);
}

TEST_CASE("push source: source.max_frame_pixels bounds the frame size", "[daemon][push][system]") {
  PushDaemon d("max_pixels", {"--set", "source.max_frame_pixels=100000"});
  sb::client::FramePusher pusher(d.pushPath);
  sb::PushedFrameHeader header = frames().header;
  header.timestamp = 1.0;
  header.fx = header.fy = 2000;
  pusher.push(header, sb::DepthRaw(400, 300, 1000));
  REQUIRE(d.waitLog("width x height = 120000", 10));
  CHECK(d.logSays("raise source.max_frame_pixels"));
  for (size_t i = 0; i < 2; ++i) push(pusher, i, 2.0 + i * 0.033);  // 320x240 = 76800 pixels: taken
  REQUIRE(sb::test::waitForPath(d.socket, 20));
  const auto deadline = Clock::now() + std::chrono::seconds(10);
  while (Clock::now() < deadline && d.framesDone() < 2)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  CHECK(d.status()["source"]["rejected"] == 1);
  int status = 0;
  d.terminate(status);
  CHECK(status == 0);
}

TEST_CASE("push source: stamps trajectory.tum could not keep are refused; the TUM reader reads it back",
          "[daemon][push][system]") {
  PushDaemon d("stamps");
  {
    sb::client::FramePusher pusher(d.pushPath);
    const double stamps[] = {1.0, 1.033, 1.033, 1.0330004, 0.5, 1e300, -1e300, 1.066, 1.1};
    for (size_t i = 0; i < std::size(stamps); ++i) push(pusher, i, stamps[i]);
    const nlohmann::json s = d.sourceAfter(4);
    CHECK(s["frames"] == 4);
    CHECK(s["rejected"] == 5);
    CHECK(d.waitTracked(4, 20));
  }
  int status = 0;
  d.terminate(status);
  CHECK(d.logSays("does not increase"));
  CHECK(d.logSays("is outside [0, 1e+10] s"));
  const std::string trajectory = d.out + "/trajectory.tum";
  CHECK(trajectoryTimestamps(trajectory) ==
        std::set<std::string>{"1.000000", "1.033000", "1.066000", "1.100000"});
  // The reader `slambooster eval` uses takes it (it refuses a stamp that does not increase).
  CHECK_NOTHROW(sb::readTumTrajectory(trajectory));
}

TEST_CASE("push source: the socket follows socket.mode; a push path that is the control socket or a file",
          "[daemon][push][system]") {
  {
    PushDaemon d("mode", {"--set", "socket.mode=0600"});
    struct stat st {};
    REQUIRE(::stat(d.pushPath.c_str(), &st) == 0);
    CHECK((st.st_mode & 0777) == 0600);
    int status = 0;
    d.terminate(status);
  }
  TempDir tmp;
  const std::string same = tmp.path + "/same.sock";
  const auto check = sb::test::runCommand(kDaemon + " --check-config --input " + same + " --socket " + same +
                                          " --set source.type=push");
  INFO(check.output);
  CHECK(check.exitCode != 0);
  CHECK(check.output.find("'source.path'") != std::string::npos);
  const std::string file = tmp.path + "/file";
  std::ofstream(file) << "a regular file\n";
  const auto run = sb::test::runCommand("timeout 20 " + kDaemon + " --input " + file + " --socket " + tmp.path +
                                        "/s.sock --out " + tmp.path + "/out --set source.type=push");
  INFO(run.output);
  CHECK(run.exitCode != 0);
  CHECK(run.output.find("set source.path") != std::string::npos);
  CHECK(run.output.find("set socket.path") == std::string::npos);
}

TEST_CASE("config: output.rotation.segment_s has a floor (S5)", "[daemon][config][system]") {
  const auto tiny = sb::test::runCommand(kDaemon + " --check-config --input " + fixture().sequence +
                                         " --set output.rotation.segment_s=1e-9");
  INFO(tiny.output);
  CHECK(tiny.exitCode != 0);
  CHECK(tiny.output.find("segment_s") != std::string::npos);
  CHECK(sb::test::runCommand(kDaemon + " --check-config --input " + fixture().sequence +
                             " --set output.rotation.segment_s=0").exitCode == 0);
}

TEST_CASE("socket: a NUL inside a request string does not cut the error text (U5)", "[daemon][protocol][system]") {
  TempDir tmp;
  const std::string socket = tmp.path + "/s.sock";
  ChildProcess d(daemonArgs(socket, sb::test::scratchDir("push_source_nul") + "/out", "recorded", "stop"), {},
                 tmp.path + "/log.txt");
  REQUIRE(sb::test::waitForPath(socket, 20));
  sb::UniqueFd fd = connectRaw(socket);
  const std::string request = "?CONTROL={\"controller\":\"a\\u0000bcd\"}\n";
  writeAll(fd.get(), request.data(), request.size());
  std::string reply;
  const auto deadline = Clock::now() + std::chrono::seconds(10);
  while (Clock::now() < deadline && reply.find("\"ERROR\"") == std::string::npos) {
    char buf[4096];
    const ssize_t n = ::recv(fd.get(), buf, sizeof buf, MSG_DONTWAIT);
    if (n > 0) reply.append(buf, size_t(n));
    else std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  char buf[4096];
  for (ssize_t n; (n = ::recv(fd.get(), buf, sizeof buf, MSG_DONTWAIT)) > 0;) reply.append(buf, size_t(n));
  INFO(reply);
  CHECK(reply.find("unknown controller") != std::string::npos);
  CHECK(reply.find("bcd") != std::string::npos);
  CHECK(reply.find("(known:") != std::string::npos);
  d.signal(SIGTERM);
  CHECK(d.wait(20) == 0);
}
