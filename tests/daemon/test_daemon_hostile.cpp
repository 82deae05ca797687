// What must neither crash slamboosterd nor lose its work (issue 23): config files that are deeply nested,
// not objects, directories or full of huge numbers (at start, with --check-config and on SIGHUP); a
// socket.max_clients the open-file limit cannot hold; and a live fuzz of the socket at the largest request
// size, from a privileged and an unprivileged client, with liveness checked throughout.

#include <grp.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <thread>

#include "core/config_reader.h"
#include "daemon/daemon_config.h"
#include "daemon/unix_socket.h"
#include "tests/daemon/daemon_e2e.h"
#include "tests/daemon/process.h"
#include "tests/daemon/server_harness.h"

using nlohmann::json;
using sb::test::ChildProcess;
using sb::test::LineClient;
using sb::test::runCommand;
using namespace sb::test::e2e;

namespace {

// A daemon's exit for a bad config: 2, its message names `needle`, and it is not an internal error.
void checkRefused(const sb::test::CommandResult& r, const std::string& needle) {
  INFO(r.output);
  CHECK(r.exitCode == 2);
  CHECK(r.output.find(needle) != std::string::npos);
  CHECK(r.output.find("internal error") == std::string::npos);
}

// `levels` nested arrays, closed: valid JSON, so that only the depth bound refuses it.
std::string deep(size_t levels) {
  return std::string(levels, '[') + std::string(levels, ']');
}

}  // namespace

TEST_CASE("slamboosterd: deep, non-object and directory configs exit 2 naming the file", "[daemon][system]") {
  TempDir tmp;
  const std::string d = kDaemon + " ";
  std::ofstream(tmp.path + "/deep.json") << "{\"source\": " << deep(70000) << "}";
  checkRefused(runCommand(d + "--config " + tmp.path + "/deep.json"), "deeper than 64 levels");
  checkRefused(runCommand(d + "--check-config --config " + tmp.path + "/deep.json"), "deep.json");
  // Not an object: refused with and without flags (a flag used to replace it with a valid object).
  for (const char* text : {"[1,2]", "\"hello\"", "{\"source\":5}"}) {
    std::ofstream(tmp.path + "/shape.json") << text;
    checkRefused(runCommand(d + "--check-config --config " + tmp.path + "/shape.json"), "a JSON object");
    checkRefused(runCommand(d + "--check-config --pacing fast --config " + tmp.path + "/shape.json"),
                 "a JSON object");
    checkRefused(runCommand(d + "--check-config --set source.speed=2 --config " + tmp.path + "/shape.json"),
                 "a JSON object");
  }
  // Syntax errors give the line and column.
  std::ofstream(tmp.path + "/syntax.json") << "{\n  \"source\": {\n    \"pacing\": fast\n  }\n}\n";
  checkRefused(runCommand(d + "--check-config --config " + tmp.path + "/syntax.json"), "line 3, column");
  // An unknown control group fails --check-config as it fails the real start.
  checkRefused(runCommand(d + "--check-config --input x --set socket.control_group=no-such-group-23"),
               "no such group");
  // A directory where a file belongs: named, exit 2 (was SIGABRT under --check-config, rc 1 otherwise).
  checkRefused(runCommand(d + "--config " + tmp.path), "is a directory");
  checkRefused(runCommand(d + "--check-config --config " + tmp.path), "is a directory");
  for (const char* key : {"slam.pipeline_config", "slam.controller_config", "power.config"}) {
    checkRefused(runCommand(d + "--check-config --input x --set " + key + "=" + tmp.path), "is a directory");
    checkRefused(runCommand(d + "--input " + fixture().sequence + " --socket " + tmp.path + "/s.sock --out " +
                            tmp.path + "/o --set " + key + "=" + tmp.path),
                 "is a directory");
  }
}

TEST_CASE("slamboosterd: a config-file fuzz never crashes --check-config", "[daemon][system]") {
  // Mutations of the documented default config: nesting, wrong types, huge numbers, truncation, directories.
  TempDir tmp;
  const json base = sb::readJsonConfig(std::string(SB_SOURCE_DIR) + "/config/slamboosterd.json", "config file");
  std::vector<std::pair<std::string, std::string>> keys;  // (section, key)
  for (auto s = base.begin(); s != base.end(); ++s)
    if (s->is_object())
      for (auto k = s->begin(); k != s->end(); ++k) keys.emplace_back(s.key(), k.key());
  const std::vector<std::string> values = {deep(100),
                                           deep(70000),
                                           "1e400",
                                           "-1e400",
                                           "18446744073709551616",
                                           "-9223372036854775809",
                                           "1e-300",
                                           "null",
                                           "[]",
                                           "{}",
                                           "\"\"",
                                           "\"" + std::string(100000, 'x') + "\"",
                                           "true",
                                           "0",
                                           "-1",
                                           "4097",
                                           "\"" + tmp.path + "\"",
                                           "[" + std::string(60, '{') + "]",
                                           "{\"a\":" + deep(64) + "}",
                                           "\"\\u0000\""};
  std::mt19937 rng(23);
  int crashes = 0;
  for (int i = 0; i < 120; ++i) {
    std::string text;
    if (i % 10 == 9) {
      text = base.dump().substr(0, rng() % base.dump().size()) + deep(rng() % 50000);  // truncated + deep
    } else {
      json j = base;
      const auto& [section, key] = keys[rng() % keys.size()];
      std::string dumped = j.dump();
      const std::string target = "\"" + key + "\":" + j[section][key].dump();
      const auto at = dumped.find(target);
      REQUIRE(at != std::string::npos);
      text = dumped.replace(at, target.size(), "\"" + key + "\":" + values[rng() % values.size()]);
    }
    const std::string path = tmp.path + "/fuzz.json";
    std::ofstream(path, std::ios::trunc) << text;
    const auto r = runCommand(kDaemon + " --check-config --config " + path + " --set source.path=x");
    INFO("case " << i << ": " << text.substr(0, 300) << "\n" << r.output.substr(0, 2000));
    CHECK((r.exitCode == 0 || r.exitCode == 2));
    CHECK(r.output.find("internal error") == std::string::npos);
    crashes += r.exitCode != 0 && r.exitCode != 2;
  }
  CHECK(crashes == 0);
}

TEST_CASE("slamboosterd: SIGHUP with a deep or broken config keeps the daemon and its pass",
          "[daemon][system]") {
  TempDir tmp;
  const std::string socket = tmp.path + "/s.sock", out = tmp.path + "/out", config = tmp.path + "/d.json";
  std::ofstream(config) << R"({"slam": {"controller": "fixed"}})";
  auto args = daemonArgs(socket, out, "recorded", "stop");
  args.insert(args.end(), {"--config", config});
  ChildProcess daemon(args, {}, tmp.path + "/daemon.log");
  REQUIRE(sb::test::waitForPath(socket, 20));
  // "power": no flag of daemonArgs touches that section (a flag used to replace a bad one with an object).
  for (const std::string& bad : {"{\"power\": " + deep(70000) + "}", std::string("[1,2]"), tmp.path}) {
    if (bad != tmp.path) {
      std::ofstream(config, std::ios::trunc) << bad;
    } else {
      std::filesystem::remove(config);
      std::filesystem::create_directory(config);  // the config path is now a directory
    }
    daemon.signal(SIGHUP);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    REQUIRE(::kill(daemon.pid(), 0) == 0);
    CHECK(ctlJson(socket, "status")["class"] == "STATUS");
    if (bad == tmp.path) std::filesystem::remove(config);
  }
  daemon.signal(SIGTERM);
  INFO(daemon.log());
  REQUIRE(daemon.wait(60) == 0);
  CHECK(daemon.log().find("reload failed") != std::string::npos);
  std::ifstream summary(out + "/summary.json");
  const size_t frames = json::parse(summary)["frames"].get<size_t>();
  CHECK(frames == dataLines(out + "/trajectory.tum"));
  CHECK(frames > 0);
}

TEST_CASE("slamboosterd: a FIFO as the config on SIGHUP or --check-config never blocks", "[daemon][system]") {
  // Issue 33: the config opened in blocking mode before the regular-file check: a FIFO stopped the event
  // loop in open() (no STATUS, SIGTERM ignored) until something wrote to the pipe.
  TempDir tmp;
  const std::string socket = tmp.path + "/s.sock", out = tmp.path + "/out", config = tmp.path + "/d.json";
  REQUIRE(::mkfifo((tmp.path + "/fifo.json").c_str(), 0600) == 0);
  checkRefused(runCommand("timeout 10 " + kDaemon + " --check-config --config " + tmp.path + "/fifo.json"),
               "named pipe (FIFO)");
  std::ofstream(config) << R"({"slam": {"controller": "fixed"}})";
  auto args = daemonArgs(socket, out, "recorded", "loop");
  args.insert(args.end(), {"--config", config});
  ChildProcess daemon(args, {}, tmp.path + "/daemon.log");
  REQUIRE(sb::test::waitForPath(socket, 20));
  std::filesystem::remove(config);
  REQUIRE(::mkfifo(config.c_str(), 0600) == 0);  // the config is now a named pipe nobody writes to
  daemon.signal(SIGHUP);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const auto asked = std::chrono::steady_clock::now();
  LineClient client(socket);
  CHECK(client.readLine(1000).find("VERSION") != std::string::npos);
  client.send("?STATUS;\n");
  CHECK(client.readLine(1000).find("\"class\":\"STATUS\"") != std::string::npos);
  CHECK(std::chrono::steady_clock::now() - asked < std::chrono::seconds(1));
  daemon.signal(SIGTERM);
  const int code = daemon.wait(2);
  INFO(daemon.log());
  CHECK(code == 0);
  CHECK(daemon.log().find("named pipe (FIFO)") != std::string::npos);  // the reload says why it failed
}

TEST_CASE("slamboosterd: socket.max_clients must fit under the open-file limit", "[daemon][system]") {
  // Issue 23: under `prlimit --nofile=64` with max_clients=4096, 80 clients ran the daemon out of
  // descriptors: accept() spun on EMFILE and the replay could not open its next frame.
  TempDir tmp;
  const auto r = runCommand("timeout 60 prlimit --nofile=64:64 " + kDaemon + " --input " +
                            fixture().sequence + " --socket " + tmp.path + "/s.sock --out " + tmp.path +
                            "/o --pacing fast --at-end exit --set socket.max_clients=4096");
  checkRefused(r, "socket.max_clients = 4096 needs");
  CHECK(r.output.find("LimitNOFILE") != std::string::npos);

  // Within the limit: 80 clients against max_clients 32 under 128 descriptors. The extra clients are
  // refused with ERROR, the log stays small, and the replay finishes every frame.
  const std::string socket = tmp.path + "/s.sock", out = tmp.path + "/out";
  auto args = daemonArgs(socket, out, "recorded", "stop");
  args.insert(args.end(), {"--set", "socket.max_clients=32"});
  ChildProcess daemon(args, {}, tmp.path + "/daemon.log", [] {
    const rlimit limit{128, 128};
    setrlimit(RLIMIT_NOFILE, &limit);
  });
  REQUIRE(sb::test::waitForPath(socket, 20));
  std::vector<std::unique_ptr<LineClient>> clients;
  size_t refused = 0;
  for (int i = 0; i < 80; ++i) {
    clients.push_back(std::make_unique<LineClient>(socket));
    const std::string greeting = clients.back()->readLine(5000);
    refused += greeting.find("too many clients") != std::string::npos;
  }
  CHECK(refused == 80 - 32);
  const auto ctl = runCommand(kCtl + " --socket " + socket + " status");
  CHECK(ctl.exitCode != 0);
  CHECK(ctl.output.find("too many clients") != std::string::npos);  // not "did not greet with VERSION"
  clients.clear();
  // The slots are free again once the server has seen the clients go (asynchronously).
  bool status = false;
  for (int i = 0; i < 100 && !status; ++i) {
    status = runCommand(kCtl + " --socket " + socket + " status").exitCode == 0;
    if (!status) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  CHECK(status);
  // Wait for the end of the pass (at_end "stop" keeps serving), then stop.
  for (int i = 0; i < 600 && dataLines(out + "/trajectory.tum") < static_cast<size_t>(kFrames); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  daemon.signal(SIGTERM);
  INFO(daemon.log());
  REQUIRE(daemon.wait(60) == 0);
  CHECK(dataLines(out + "/trajectory.tum") == static_cast<size_t>(kFrames));
  CHECK(daemon.log().size() < 20000);
}

namespace {

constexpr size_t kMaxRequest = 1 << 20;  // the largest socket.max_request_bytes allowed

// One fuzzed request line (no '\n'), up to a little over kMaxRequest bytes.
std::string fuzzRequest(std::mt19937& rng) {
  const auto pick = [&](size_t n) { return static_cast<size_t>(rng() % n); };
  const size_t roll = pick(100);
  const size_t size = roll < 80 ? pick(200) : roll < 95 ? pick(65536) : pick(kMaxRequest);
  std::string nest;
  for (size_t i = 0; i < size / 5; ++i) nest += "{\"a\":";
  const std::string inserts[] = {
      "?CONTROL={\"unpin\":" + std::string(size, '['),
      "?CONTROL={\"unpin\":" + deep(size / 2) + "}",
      "?WATCH={\"enable\":false,\"x\":" + nest,
      "?CONTROL={\"controller\":\"" + std::string(size, 'x') + "\"}",
      "?CONTROL={\"pin\":{\"" + std::string(size, 'k') + "\":1}}",
      "?CONTROL={\"pin\":{\"csr\":1e400}}",
      "?CONTROL={\"pin\":{\"csr\":2}}",
      "?CONTROL={\"unpin\":\"all\"}",
      "?CONTROL={\"unpin\":[[[[[\"csr\"]]]]]}",
      "?WATCH={\"enable\":false,\"pose\":" + deep(60) + "}",
      "?POLL;",
      "?STATUS;",
      "?VERSION;",
      std::string(kMaxRequest + 10, '?'),
      "?STATUS={" + std::string(size, ' '),
  };
  std::string r = inserts[pick(std::size(inserts))];
  if (pick(4) == 0) {  // mutate: random bytes at random places
    for (size_t i = 0, n = 1 + pick(8); i < n && !r.empty(); ++i)
      r[pick(r.size())] = static_cast<char>(rng());
  }
  if (pick(8) == 0) {
    r.clear();
    for (size_t i = 0, n = 1 + pick(300); i < n; ++i) r += static_cast<char>(rng());
  }
  for (char& c : r)
    if (c == '\n') c = ' ';
  if (r.find_first_not_of(" \r") == std::string::npos) r = "?POLL;";
  return r;
}

// Sends `count` fuzzed requests on one connection and reads one reply to each (skipping streamed reports).
// Returns "" or what went wrong. Used by the test process and by an unprivileged child.
std::string fuzzConnectionOrThrow(const std::string& socket, unsigned seed, int count) {
  std::mt19937 rng(seed);
  LineClient c(socket);
  if (c.readLine().find("\"VERSION\"") == std::string::npos) return "no VERSION greeting";
  std::string history;
  for (int i = 0; i < count; ++i) {
    const std::string request = fuzzRequest(rng);
    history += std::to_string(i) + ": " + std::to_string(request.size()) + " " + request.substr(0, 60) + "\n";
    c.send(request + "\n");
    while (true) {
      const std::string line = c.readLine(10000);
      if (line.empty())
        return "no reply to request " + std::to_string(i) + " (" + std::to_string(request.size()) +
               " bytes, " + (c.closedWithin(0) ? "connection closed" : "timed out") +
               "): " + request.substr(0, 100) + "\n" + history;
      const json reply = json::parse(line, nullptr, false);
      if (!reply.is_object() || !reply.contains("class")) return "bad reply: " + line.substr(0, 200);
      const std::string cls = reply["class"];
      if (cls != "POSE" && cls != "KNOBS" && cls != "ENERGY") break;
    }
  }
  return "";
}

std::string fuzzConnection(const std::string& socket, unsigned seed, int count) {
  try {
    return fuzzConnectionOrThrow(socket, seed, count);
  } catch (const std::exception& e) {
    return std::string("client failed: ") + e.what();
  }
}

// A fresh client gets VERSION and a STATUS within 5 s.
bool alive(const std::string& socket) {
  LineClient c(socket);
  if (c.readLine(5000).find("\"VERSION\"") == std::string::npos) return false;
  c.send("?STATUS;\n");
  for (std::string line; !(line = c.readLine(5000)).empty();)
    if (line.find("\"STATUS\"") != std::string::npos) return true;
  return false;
}

}  // namespace

TEST_CASE("slamboosterd: live fuzz at the largest request size, privileged and not", "[daemon][system]") {
  TempDir tmp;
  ::chmod(tmp.path.c_str(), 0755);
  const std::string socket = tmp.path + "/s.sock", out = tmp.path + "/out";
  auto args = daemonArgs(socket, out, "recorded", "loop");
  args.insert(args.end(), {"--set", "socket.max_request_bytes=" + std::to_string(kMaxRequest), "--set",
                           "socket.mode=0666", "--set", "log_level=debug"});
  ChildProcess daemon(args, {}, tmp.path + "/daemon.log");
  REQUIRE(sb::test::waitForPath(socket, 20));

  // The unprivileged client: a child process as nobody (CI runs as root; skipped otherwise).
  pid_t child = -1;
  if (::geteuid() == 0) {
    child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) {
      if (::setgroups(0, nullptr) != 0 || ::setgid(65534) != 0 || ::setuid(65534) != 0) ::_exit(3);
      std::string problem;
      for (int round = 0; round < 10 && problem.empty(); ++round)
        problem = fuzzConnection(socket, 1000 + round, 150);
      if (!problem.empty()) (void)!::write(2, problem.data(), problem.size());
      ::_exit(problem.empty() ? 0 : 1);
    }
  } else {
    WARN("not root: the unprivileged half of the live fuzz is skipped");
  }
  for (int round = 0; round < 10; ++round) {
    INFO("round " << round << "\n" << daemon.log().substr(0, 4000));
    CHECK(fuzzConnection(socket, static_cast<unsigned>(round), 150) == "");
    REQUIRE(::kill(daemon.pid(), 0) == 0);
    REQUIRE(alive(socket));
  }
  if (child > 0) {
    int status = 0;
    REQUIRE(::waitpid(child, &status, 0) == child);
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
  }
  REQUIRE(alive(socket));
  // Every reply is short: no client was dropped for a reply its buffer could not hold (debug log).
  CHECK(daemon.log().find("not reading (output queue full") == std::string::npos);
  daemon.signal(SIGTERM);
  INFO(daemon.log().substr(0, 4000));
  CHECK(daemon.wait(60) == 0);
}
