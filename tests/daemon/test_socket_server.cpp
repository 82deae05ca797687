// The socket server under abuse: oversize lines, binary floods, half lines and disconnects, clients that
// never read, too many clients, unauthorised ?CONTROL. The server must answer ERROR where a reply makes
// sense, keep serving everyone else, and never block.

#include <fcntl.h>
#include <pwd.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <thread>
#include <tuple>
#include <vector>

#include "tests/daemon/server_harness.h"

using nlohmann::json;
using sb::test::LineClient;
using sb::test::ServerHarness;

namespace {

json readJson(LineClient& c) {
  const std::string line = c.readLine();
  INFO("line: " << line);
  REQUIRE_FALSE(line.empty());
  return json::parse(line);
}

size_t clientCount(ServerHarness& server) {
  size_t n = 0;
  server.sync([&](sb::daemon::SocketServer& s) { n = s.clientCount(); });
  return n;
}

}  // namespace

TEST_CASE("an oversize request line gets one ERROR and the connection stays usable", "[daemon][socket]") {
  sb::daemon::SocketConfig config;
  config.maxRequestBytes = 100;
  ServerHarness server(config);
  LineClient c(server.path());
  CHECK(readJson(c)["class"] == "VERSION");
  c.send("?WATCH={\"enable\":true" + std::string(5000, ' ') + "}\n?POLL;\n");
  const json error = readJson(c);
  CHECK(error["class"] == "ERROR");
  CHECK(error["message"].get<std::string>().find("longer than 100 bytes") != std::string::npos);
  CHECK(readJson(c)["class"] == "POLL");
  // Exactly at the limit is fine.
  std::string exact = "?WATCH={\"enable\":false";
  exact += std::string(100 - exact.size() - 1, ' ') + "}";
  REQUIRE(exact.size() == 100);
  c.send(exact + "\n");
  CHECK(readJson(c)["class"] == "WATCH");
}

TEST_CASE("binary garbage and half lines then disconnect leave the server unharmed", "[daemon][socket]") {
  ServerHarness server;
  {
    LineClient flood(server.path());
    std::mt19937 rng(7);
    std::string garbage(1 << 20, '\0');
    for (auto& ch : garbage) ch = static_cast<char>(rng());
    // The server answers ERRORs; we never read them: it must drop, not block.
    (void)::send(flood.fd(), garbage.data(), garbage.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
  }
  {
    LineClient half(server.path());
    half.send("?WATCH={\"enable\":tr");  // and hang up mid-line
  }
  LineClient ok(server.path());
  CHECK(readJson(ok)["class"] == "VERSION");
  ok.send("?STATUS;\n");
  CHECK(readJson(ok)["class"] == "STATUS");
  // The two broken clients are gone.
  for (int i = 0; i < 100 && clientCount(server) != 1; ++i) usleep(10000);
  CHECK(clientCount(server) == 1);
}

TEST_CASE("a client that never reads is dropped then disconnected; readers get every POSE in order",
          "[daemon][socket]") {
  sb::daemon::SocketConfig config;
  config.clientBufferBytes = 64 * 1024;
  config.clientStallSeconds = 0.2;
  ServerHarness server(config);
  LineClient reader(server.path());
  LineClient sleeper(server.path());
  // The sleeper asks for everything and never reads again; a tiny receive buffer fills at once.
  const int small = 4096;
  setsockopt(sleeper.fd(), SOL_SOCKET, SO_RCVBUF, &small, sizeof small);
  sleeper.send("?WATCH={\"enable\":true}\n");
  reader.send("?WATCH={\"enable\":true,\"knobs\":false}\n");
  CHECK(readJson(reader)["class"] == "VERSION");
  CHECK(readJson(reader)["class"] == "WATCH");
  constexpr int kFrames = 2000;
  // The reader reads continuously on its own thread, like a live client.
  int received = 0;
  bool inOrder = true;
  std::thread readerThread([&] {
    while (received < kFrames) {
      const std::string line = reader.readLine(5000);
      if (line.empty()) return;
      const json j = json::parse(line);
      inOrder = inOrder && j["class"] == "POSE" && j["frame"] == received;
      ++received;
    }
  });
  for (int f = 0; f < kFrames; ++f) {
    server.publishFrame(sb::test::scriptedFrame(f));
    if (f % 100 == 99) usleep(50000);  // lets the stall timer run out while frames still flow
  }
  readerThread.join();
  CHECK(received == kFrames);
  CHECK(inOrder);
  CHECK(sleeper.closedWithin(5000));
  uint64_t dropped = 0, disconnected = 0;
  server.sync([&](sb::daemon::SocketServer& s) {
    dropped = s.messagesDropped();
    disconnected = s.clientsDisconnected();
  });
  CHECK(dropped > 0);
  CHECK(disconnected == 1);
}

TEST_CASE("connections beyond max_clients get ERROR and are closed", "[daemon][socket]") {
  sb::daemon::SocketConfig config;
  config.maxClients = 2;
  ServerHarness server(config);
  LineClient a(server.path()), b(server.path());
  CHECK(readJson(a)["class"] == "VERSION");
  CHECK(readJson(b)["class"] == "VERSION");
  LineClient c(server.path());
  const json e = readJson(c);
  CHECK(e["class"] == "ERROR");
  CHECK(e["message"].get<std::string>().find("too many clients") != std::string::npos);
  CHECK(c.closedWithin(2000));
  a.close();
  for (int i = 0; i < 100 && clientCount(server) != 1; ++i) usleep(10000);
  LineClient d(server.path());
  CHECK(readJson(d)["class"] == "VERSION");
}

TEST_CASE("?CONTROL from a peer that is not root, the daemon's user or in the group is refused",
          "[daemon][socket]") {
  // The server's "own" uid is one nobody has; the client is this process, or (as root) a child that drops
  // to nobody first, since root is always allowed.
  const bool root = ::geteuid() == 0;
  const passwd* nobody = getpwnam("nobody");
  if (root && !nobody) {
    WARN("no user 'nobody': cannot run the denial check as root");
    return;
  }
  sb::daemon::SocketConfig config;
  config.mode = 0666;  // so that nobody may connect at all
  ServerHarness server(config, root ? static_cast<uid_t>(-2) : ::geteuid() + 12345);
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    if (root && setuid(nobody->pw_uid) != 0) _exit(3);
    try {
      LineClient c(server.path());
      c.readLine();
      // A valid request, then one whose argument is never parsed for a client without permission.
      c.send("?CONTROL={\"controller\":\"slambooster\"}\n?CONTROL={\"unpin\":" + std::string(3000, '[') + "\n");
      for (int i = 0; i < 2; ++i) {
        const json e = json::parse(c.readLine());
        if (e["class"] != "ERROR" || e["message"].get<std::string>().find("permission denied") == std::string::npos)
          _exit(1);
      }
      _exit(0);
    } catch (...) {
      _exit(2);
    }
  }
  int status = 0;
  waitpid(child, &status, 0);
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
  CHECK(server.state.controls.empty());
}

TEST_CASE("control policy: root, the daemon's user and the configured group", "[daemon][socket]") {
  sb::daemon::ControlPolicy policy(1000, "4242");
  sb::daemon::PeerCredentials p;
  p.uid = 0;
  CHECK(policy.allowed(p));
  p.uid = 1000;
  CHECK(policy.allowed(p));
  p.uid = 1001;
  p.gid = 100;
  CHECK_FALSE(policy.allowed(p));
  p.gid = 4242;
  CHECK(policy.allowed(p));
  p.gid = 100;
  p.groups = {27, 4242};
  CHECK(policy.allowed(p));
  sb::daemon::ControlPolicy noGroup(1000, "");
  CHECK_FALSE(noGroup.allowed(p));
  CHECK_THROWS_WITH(sb::daemon::ControlPolicy(1000, "no-such-group-sb"), Catch::Contains("no such group"));
}

TEST_CASE("out of descriptors, the server pauses accepting instead of spinning", "[daemon][socket]") {
  // Issue 23: accept() failing with EMFILE left the connection queued, epoll reported it again at once, and
  // the event loop spun (64,375 warnings in 0.2 s).
  ServerHarness server;
  rlimit saved{};
  REQUIRE(getrlimit(RLIMIT_NOFILE, &saved) == 0);
  // Fill the descriptor table up to a lowered soft limit, keeping one for the client's own socket.
  std::vector<sb::UniqueFd> filler;
  const rlimit low{256, saved.rlim_max};
  REQUIRE(setrlimit(RLIMIT_NOFILE, &low) == 0);
  while (true) {
    sb::UniqueFd fd(::open("/dev/null", O_RDONLY | O_CLOEXEC));
    if (!fd.valid()) break;
    filler.push_back(std::move(fd));
  }
  REQUIRE(filler.size() > 2);
  filler.pop_back();  // one free descriptor: the client's socket; the server's accept() gets EMFILE
  auto client = std::make_unique<LineClient>(server.path());
  const auto cpuSeconds = [] {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_utime.tv_sec + u.ru_stime.tv_sec + (u.ru_utime.tv_usec + u.ru_stime.tv_usec) / 1e6;
  };
  const double cpuBefore = cpuSeconds();
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  const double cpu = cpuSeconds() - cpuBefore;
  uint64_t pauses = 0;
  server.sync([&](sb::daemon::SocketServer& s) { pauses = s.acceptPauses(); });
  filler.clear();
  REQUIRE(setrlimit(RLIMIT_NOFILE, &saved) == 0);
  CHECK(cpu < 0.3);  // a spinning loop burns a whole core
  CHECK(pauses == 1);
  // Descriptors are back: the next housekeeping tick listens again and the queued client is greeted.
  server.sync([](sb::daemon::SocketServer& s) { s.resumeAccepting(); });
  CHECK(readJson(*client)["class"] == "VERSION");
  CHECK(clientCount(server) == 1);
}

TEST_CASE("one user cannot hold every slot: a per-uid cap and slots kept for root", "[daemon][socket]") {
  // Issue 23: one unprivileged user could open socket.max_clients connections and lock out root.
  const passwd* nobody = getpwnam("nobody");
  if (::geteuid() != 0 || !nobody) {
    WARN("needs root (to connect as nobody): skipped");
    return;
  }
  // In a child as nobody: opens `count` clients, reports how many were greeted and what the first refusal
  // said, then holds them until the parent closes the pipe.
  const auto asNobody = [&](const std::string& path, int count, std::string& refusal) {
    int report[2], hold[2];
    REQUIRE(::pipe(report) == 0);
    REQUIRE(::pipe(hold) == 0);
    const pid_t child = fork();
    REQUIRE(child >= 0);
    if (child == 0) {
      ::close(report[0]);
      ::close(hold[1]);
      if (setuid(nobody->pw_uid) != 0) _exit(3);
      std::vector<std::unique_ptr<LineClient>> clients;
      std::string first;
      int greeted = 0;
      for (int i = 0; i < count; ++i) {
        clients.push_back(std::make_unique<LineClient>(path));
        const std::string line = clients.back()->readLine();
        if (line.find("\"VERSION\"") != std::string::npos)
          ++greeted;
        else if (first.empty())
          first = line;
      }
      const std::string msg = std::to_string(greeted) + "\n" + first;
      (void)!::write(report[1], msg.data(), msg.size());
      ::close(report[1]);
      char c;
      (void)!::read(hold[0], &c, 1);  // until the parent closes it
      _exit(0);
    }
    ::close(report[1]);
    ::close(hold[0]);
    std::string msg;
    char buf[4096];
    for (ssize_t n; (n = ::read(report[0], buf, sizeof buf)) > 0;) msg.append(buf, static_cast<size_t>(n));
    ::close(report[0]);
    refusal = msg.substr(msg.find('\n') + 1);
    return std::make_tuple(std::stoi(msg.substr(0, msg.find('\n'))), hold[1], child);
  };
  const auto finish = [](int holdFd, pid_t child) {
    ::close(holdFd);
    int status = 0;
    waitpid(child, &status, 0);
    CHECK(WIFEXITED(status));
  };

  sb::daemon::SocketConfig config;
  config.mode = 0666;
  config.maxClients = 12;
  config.maxClientsPerUid = 3;
  {
    ServerHarness server(config);
    std::string refusal;
    const auto [greeted, hold, child] = asNobody(server.path(), 5, refusal);
    CHECK(greeted == 3);
    CHECK_THAT(refusal, Catch::Contains("too many clients for uid " + std::to_string(nobody->pw_uid)) &&
                            Catch::Contains("socket.max_clients_per_uid"));
    finish(hold, child);
  }
  config.maxClients = 8;  // 2 slots kept for privileged clients
  config.maxClientsPerUid = 8;
  {
    ServerHarness server(config);
    std::string refusal;
    const auto [greeted, hold, child] = asNobody(server.path(), 8, refusal);
    CHECK(greeted == 6);
    CHECK_THAT(refusal, Catch::Contains("kept for privileged clients"));
    LineClient root(server.path());  // root still gets in
    CHECK(readJson(root)["class"] == "VERSION");
    finish(hold, child);
  }
}

TEST_CASE("a '\\r' before '\\n' does not count against max_request_bytes", "[daemon][socket]") {
  sb::daemon::SocketConfig config;
  config.maxRequestBytes = 100;
  ServerHarness server(config);
  LineClient c(server.path());
  CHECK(readJson(c)["class"] == "VERSION");
  std::string exact = "?WATCH={\"enable\":false";
  exact += std::string(100 - exact.size() - 1, ' ') + "}";
  REQUIRE(exact.size() == 100);
  c.send(exact + "\r\n");
  CHECK(readJson(c)["class"] == "WATCH");
  c.send(exact + "\r");  // the '\r' ends one read, the '\n' comes in the next
  usleep(50000);
  c.send("\n");
  CHECK(readJson(c)["class"] == "WATCH");
  c.send(exact + " \r\n");  // one byte too many
  CHECK(readJson(c)["class"] == "ERROR");
}

TEST_CASE("clients flooding ?STATUS; do not delay a watcher's POSE", "[daemon][socket]") {
  // Issue 33: a client's whole 64 KiB read (~7000 pipelined requests) was served in one event-loop turn, so
  // POSE waited behind every flooder's turn. Requests are now served within per-client, per-uid and per-turn
  // budgets. (scripts/bench_flood.sh measures the latency against the real daemon; this bound is loose.)
  sb::daemon::SocketConfig config;
  config.maxClients = 64;
  ServerHarness server(config);
  LineClient watcher(server.path());
  watcher.send("?WATCH={\"enable\":true,\"knobs\":false,\"energy\":false}\n");
  CHECK(readJson(watcher)["class"] == "VERSION");
  CHECK(readJson(watcher)["class"] == "WATCH");
  constexpr int kFlooders = 24, kFrames = 60;
  std::vector<std::unique_ptr<LineClient>> flooders;
  for (int i = 0; i < kFlooders; ++i) flooders.push_back(std::make_unique<LineClient>(server.path()));
  std::atomic<bool> flooding{true};
  std::atomic<long> replies{0};
  std::thread flood([&] {  // one thread: keeps every flooder's socket full of requests and reads every reply
    std::string block;
    for (int i = 0; i < 455; ++i) block += "?STATUS;\n";
    char buf[65536];
    while (flooding) {
      for (auto& f : flooders) {
        (void)!::send(f->fd(), block.data(), block.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
        for (ssize_t n; (n = ::recv(f->fd(), buf, sizeof buf, MSG_DONTWAIT)) > 0;)
          replies += std::count(buf, buf + n, '\n');
      }
    }
  });
  usleep(300000);  // the flood is under way
  using Clock = std::chrono::steady_clock;
  std::vector<Clock::time_point> sent(kFrames);
  std::vector<double> latencyMs;
  std::thread reader([&] {
    while (static_cast<int>(latencyMs.size()) < kFrames) {
      const std::string line = watcher.readLine(10000);
      if (line.empty()) return;
      const json j = json::parse(line);
      if (j["class"] == "POSE")
        latencyMs.push_back(std::chrono::duration<double, std::milli>(Clock::now() - sent[j["frame"]]).count());
    }
  });
  for (int f = 0; f < kFrames; ++f) {
    sent[f] = Clock::now();
    server.publishFrame(sb::test::scriptedFrame(f));
    usleep(20000);
  }
  reader.join();
  flooding = false;
  flood.join();
  REQUIRE(latencyMs.size() == kFrames);
  std::sort(latencyMs.begin(), latencyMs.end());
  const double p50 = latencyMs[kFrames / 2], p95 = latencyMs[kFrames * 95 / 100];
  INFO("POSE latency with " << kFlooders << " flooders: p50 " << p50 << " ms, p95 " << p95 << " ms, max "
                            << latencyMs.back() << " ms; " << replies.load() << " STATUS replies");
  CHECK(replies.load() > 1000);  // the flood was served too
  CHECK(p95 < 200.0);
}
