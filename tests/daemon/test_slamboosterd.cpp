// slamboosterd end to end, as systemd and users run it: a short synthetic replay, slamboosterctl against
// the real socket, SIGTERM mid-run, SIGHUP reload, a fake NOTIFY_SOCKET, socket activation, exit code 2
// for bad configuration, and the retention of a looping replay's pass directories.

#include <fcntl.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "core/unique_fd.h"
#include "daemon/unix_socket.h"
#include "tests/daemon/daemon_e2e.h"
#include "tests/daemon/process.h"
#include "tests/support/constant_power.h"
#include "tests/support/files.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

namespace fs = std::filesystem;
using nlohmann::json;
using sb::test::ChildProcess;
using sb::test::runCommand;

using namespace sb::test::e2e;

TEST_CASE("slamboosterd: watch, then SIGTERM mid-run: every processed frame is on disk, exit 0",
          "[daemon][system]") {
  TempDir tmp;
  const std::string socket = tmp.path + "/s.sock", out = tmp.path + "/out";
  auto args = daemonArgs(socket, out, "recorded", "stop");
  args.insert(args.end(), {"--set", "source.speed=0.5"});  // 2 s of input: SIGTERM lands mid-run even on a fast machine
  ChildProcess d(args, {}, tmp.path + "/log.txt");
  REQUIRE(sb::test::waitForPath(socket, 20));

  const auto watch = runCommand(kCtl + " --json --socket " + socket + " watch --count 3 --no-knobs");
  INFO(watch.output << d.log());
  REQUIRE(watch.exitCode == 0);
  std::vector<json> poses;
  std::istringstream lines(watch.output);
  for (std::string line; std::getline(lines, line);) poses.push_back(json::parse(line));
  REQUIRE(poses.size() == 3);
  for (size_t i = 0; i < poses.size(); ++i) {
    CHECK(poses[i]["class"] == "POSE");
    if (i > 0) CHECK(poses[i]["frame"].get<int>() == poses[i - 1]["frame"].get<int>() + 1);
  }
  const auto human = runCommand(kCtl + " --socket " + socket + " status");
  CHECK(human.exitCode == 0);
  CHECK(human.output.find("controller    fixed") != std::string::npos);
  // scripts/main_job.sh prints this row as its progress line (it once scrambled numbers picked from the JSON).
  CHECK_THAT(human.output, Catch::Matches("(.|\\n)*\\n  frames +[0-9]+ processed, [0-9]+ tracked, [0-9.]+ fps, "
                                          "[0-9.]+ ms/frame computation\\n(.|\\n)*"));

  d.signal(SIGTERM);
  REQUIRE(d.wait(30) == 0);
  CHECK(d.log().find("SIGTERM") != std::string::npos);
  const size_t frames = dataLines(out + "/frames.jsonl");
  CHECK(frames >= 3);
  CHECK(frames < static_cast<size_t>(kFrames));  // it really stopped mid-run
  CHECK(dataLines(out + "/trajectory.tum") == frames);
  std::ifstream summaryFile(out + "/summary.json");
  CHECK(json::parse(summaryFile)["frames"].get<size_t>() == frames);
  // The watched poses are in the trajectory (same timestamps, as the TUM writer prints them).
  const auto stamps = trajectoryTimestamps(out + "/trajectory.tum");
  for (const auto& p : poses) {
    char ts[32];
    std::snprintf(ts, sizeof ts, "%.6f", p["timestamp"].get<double>());
    CHECK(stamps.count(ts) == 1);
  }
  CHECK_FALSE(fs::exists(socket));  // removed on exit
}

TEST_CASE("slamboosterd: at_end=exit replays every frame and exits 0", "[daemon][system]") {
  TempDir tmp;
  const std::string socket = tmp.path + "/s.sock", out = tmp.path + "/out";
  auto args = daemonArgs(socket, out, "fast", "exit");
  args.insert(args.end(), {"--set", "source.max_frames=10"});
  ChildProcess d(args, {}, tmp.path + "/log.txt");
  INFO(d.log());
  REQUIRE(d.wait(60) == 0);
  CHECK(dataLines(out + "/trajectory.tum") == 10);
  CHECK(dataLines(out + "/frames.jsonl") == 10);
  CHECK(fs::file_size(out + "/report.html") > 0);  // output.report defaults to true
}

namespace {

// Waits until pass directory `n` exists (a looping replay got that far).
bool waitForPass(const std::string& out, int n) {
  return sb::test::waitForPath(passDirectory(out, n), 60);
}

}  // namespace

TEST_CASE("slamboosterd: a looping replay keeps its passes within the retention; a restart numbers on",
          "[daemon][system]") {
  // Before (issue 34), every pass of a looping replay left a directory behind, without limit.
  TempDir tmp;
  const std::string socket = tmp.path + "/s.sock", out = tmp.path + "/out";
  auto args = daemonArgs(socket, out, "fast", "loop");
  args.insert(args.end(), {"--set", "source.max_frames=5", "--set", "output.report=false", "--set",
                           "output.rotation.keep_segments=2"});
  {
    ChildProcess d(args, {}, tmp.path + "/log1.txt");
    REQUIRE(waitForPass(out, 6));
    const json status = ctlJson(socket, "status");
    INFO(status.dump(1) << d.log());
    CHECK(status["disk"]["rotation"] == false);  // a replay: single files, but its passes under retention
    CHECK(status["disk"]["removed_segments"].get<int>() >= 3);
    d.signal(SIGTERM);
    REQUIRE(d.wait(30) == 0);
  }
  std::vector<int> passes = passDirectories(out);
  INFO("passes after the first start: " << passes.size());
  REQUIRE(passes.size() <= 3);  // two ended passes and the last one
  CHECK(passes.back() >= 6);
  CHECK(passes.front() >= passes.back() - 2);
  const int last = passes.back();
  // A restart keeps the directories there (within the limit) and numbers on after them.
  ChildProcess d(args, {}, tmp.path + "/log2.txt");
  REQUIRE(waitForPass(out, last + 2));
  d.signal(SIGTERM);
  INFO(d.log());
  REQUIRE(d.wait(30) == 0);
  passes = passDirectories(out);
  REQUIRE(passes.size() <= 3);
  CHECK(passes.front() > last - 2);
  CHECK(passes.back() >= last + 2);
  CHECK(sb::test::readJson(passDirectory(out, passes.front()) + "/summary.json")["complete"] == true);
}

TEST_CASE("slamboosterd: ?CONTROL and SIGHUP switch the controller; pins apply", "[daemon][system]") {
  TempDir tmp;
  const std::string socket = tmp.path + "/s.sock", out = tmp.path + "/out";
  const std::string controllerFile = tmp.path + "/controller.json";
  std::ofstream(controllerFile) << R"({"name": "fixed"})";
  auto args = daemonArgs(socket, out, "recorded", "stop");
  args.insert(args.end(), {"--set", "slam.controller_config=" + controllerFile, "--set", "source.speed=0.3"});
  ChildProcess d(args, {}, tmp.path + "/log.txt");
  REQUIRE(sb::test::waitForPath(socket, 20));
  INFO(d.log());

  const json control = ctlJson(socket, "control --pin csr=4");
  CHECK(control["class"] == "CONTROL");
  CHECK(control["pinned"]["csr"] == 4.0);
  const auto refused = runCommand(kCtl + " --socket " + socket + " control --controller nosuch");
  CHECK(refused.exitCode == 1);
  CHECK(refused.output.find("unknown controller 'nosuch'") != std::string::npos);

  // A KNOBS after the pin shows csr 4 and names the pin.
  const auto watch = runCommand(kCtl + " --json --socket " + socket + " watch --count 2 --no-pose");
  REQUIRE(watch.exitCode == 0);
  const json knobs = json::parse(watch.output.substr(watch.output.rfind('{')));
  CHECK(knobs["csr"] == 4);
  CHECK(knobs["pinned"] == json::array({"csr"}));

  std::ofstream(controllerFile) << R"({"name": "accurate"})";
  d.signal(SIGHUP);
  std::string controller;
  for (int i = 0; i < 100 && controller != "accurate"; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    controller = ctlJson(socket, "status")["controller"].get<std::string>();
  }
  CHECK(controller == "accurate");
  CHECK(d.log().find("controller settings reloaded") != std::string::npos);
  d.signal(SIGTERM);
  CHECK(d.wait(30) == 0);
}

TEST_CASE("slamboosterd: READY, STATUS and WATCHDOG reach a fake NOTIFY_SOCKET", "[daemon][system]") {
  TempDir tmp;
  const std::string notifyPath = tmp.path + "/notify";
  sb::UniqueFd notify(socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0));
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::snprintf(addr.sun_path, sizeof addr.sun_path, "%s", notifyPath.c_str());
  REQUIRE(bind(notify.get(), reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0);
  const timeval timeout{0, 200000};
  setsockopt(notify.get(), SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);

  const std::string socket = tmp.path + "/s.sock";
  ChildProcess d(daemonArgs(socket, tmp.path + "/out", "recorded", "stop"),
                 {"NOTIFY_SOCKET=" + notifyPath, "WATCHDOG_USEC=400000"}, tmp.path + "/log.txt");
  bool ready = false, status = false;
  int watchdogs = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (std::chrono::steady_clock::now() < deadline && !(ready && status && watchdogs >= 3)) {
    char buf[4096];
    const ssize_t n = recv(notify.get(), buf, sizeof buf, 0);
    if (n <= 0) continue;
    const std::string msg(buf, static_cast<size_t>(n));
    ready = ready || msg.find("READY=1") != std::string::npos;
    status = status || msg.find("STATUS=") != std::string::npos;
    if (msg.find("WATCHDOG=1") != std::string::npos) {
      CHECK(ready);  // watchdog pings come after READY
      ++watchdogs;
    }
  }
  INFO(d.log());
  CHECK(ready);
  CHECK(status);
  CHECK(watchdogs >= 3);
  d.signal(SIGTERM);
  bool stopping = false;
  for (int i = 0; i < 100 && !stopping; ++i) {
    char buf[4096];
    const ssize_t n = recv(notify.get(), buf, sizeof buf, 0);
    if (n > 0) stopping = std::string(buf, static_cast<size_t>(n)).find("STOPPING=1") != std::string::npos;
  }
  CHECK(stopping);
  CHECK(d.wait(30) == 0);
}

TEST_CASE("slamboosterd: socket activation through LISTEN_FDS", "[daemon][system]") {
  TempDir tmp;
  const std::string socket = tmp.path + "/activated.sock";
  sb::daemon::ListeningSocket listener = sb::daemon::openListeningSocket(socket, 0660);
  const int fd = listener.fd.get();
  ChildProcess d(daemonArgs(tmp.path + "/unused.sock", tmp.path + "/out", "recorded", "stop"), {},
                 tmp.path + "/log.txt", [fd] {
                   if (fd == 3)
                     fcntl(fd, F_SETFD, 0);  // dup2 onto itself would keep close-on-exec
                   else
                     dup2(fd, 3);  // SD_LISTEN_FDS_START
                   setenv("LISTEN_FDS", "1", 1);
                   setenv("LISTEN_PID", std::to_string(getpid()).c_str(), 1);
                 });
  const auto status = runCommand(kCtl + " --json --socket " + socket + " status");
  INFO(status.output << "\ndaemon log:\n" << d.log());
  CHECK(status.exitCode == 0);
  CHECK(status.output.find("\"class\":\"STATUS\"") != std::string::npos);
  CHECK_FALSE(fs::exists(tmp.path + "/unused.sock"));
  d.signal(SIGTERM);
  CHECK(d.wait(30) == 0);
  CHECK(fs::exists(socket));  // systemd's socket: the daemon does not remove it
  CHECK(d.log().find("socket activation") != std::string::npos);
}

TEST_CASE("slamboosterd: bad configuration exits 2 naming the key, the value and what is allowed",
          "[daemon][system]") {
  TempDir tmp;
  const auto run = [&](const std::string& args) { return runCommand(kDaemon + " " + args); };
  auto r = run("--input x --set socket.max_clients=0");
  CHECK(r.exitCode == 2);
  CHECK(r.output.find("'socket.max_clients' = 0") != std::string::npos);
  CHECK(r.output.find("[1, 4096]") != std::string::npos);
  r = run("--config " + tmp.path + "/missing.json");
  CHECK(r.exitCode == 2);
  CHECK(r.output.find("missing.json") != std::string::npos);
  std::ofstream(tmp.path + "/bad.json") << R"({"socket": {"mode": "0999"}})";
  r = run("--config " + tmp.path + "/bad.json");
  CHECK(r.exitCode == 2);
  CHECK(r.output.find("'socket.mode' = \"0999\"") != std::string::npos);
  r = run("--socket " + tmp.path + "/s.sock --out " + tmp.path + "/o");
  CHECK(r.exitCode == 2);
  CHECK(r.output.find("source.path is empty") != std::string::npos);
  std::ofstream(tmp.path + "/pipe.json") << R"({"volume_resolutoin": 64})";
  r = run("--input " + fixture().sequence + " --socket " + tmp.path + "/s.sock --out " + tmp.path +
          "/o --set slam.pipeline_config=" + tmp.path + "/pipe.json");
  CHECK(r.exitCode == 2);
  CHECK(r.output.find("volume_resolutoin") != std::string::npos);
  // A power config named explicitly must exist (only the packaged default path may be absent).
  r = run("--input " + fixture().sequence + " --socket " + tmp.path + "/s.sock --out " + tmp.path +
          "/o --set power.config=" + tmp.path + "/no-power.json");
  CHECK(r.exitCode == 2);
  CHECK(r.output.find("no-power.json") != std::string::npos);
  r = run("--input " + tmp.path + "/no-such-sequence --socket " + tmp.path + "/s.sock --out " + tmp.path +
          "/o");
  CHECK(r.exitCode == 1);
  CHECK(r.output.find("no-such-sequence") != std::string::npos);
  CHECK(run("--check-config --input x").exitCode == 0);
  // --check-config reads the files the config names, as start-up would (the input is not opened).
  r = run("--check-config --input x --set power.config=" + tmp.path + "/no-power.json");
  CHECK(r.exitCode == 2);
  CHECK(r.output.find("no-power.json") != std::string::npos);
  r = run("--check-config --input x --set slam.pipeline_config=" + tmp.path + "/pipe.json");
  CHECK(r.exitCode == 2);
  CHECK(r.output.find("volume_resolutoin") != std::string::npos);
  std::ofstream(tmp.path + "/controller.json") << R"({"controller": {"name": "slambooster", "slambooster": {"v_low_m_per_frame": "x"}}})";
  r = run("--check-config --input x --set slam.controller_config=" + tmp.path + "/controller.json");
  CHECK(r.exitCode == 2);
  CHECK(r.output.find("controller.json") != std::string::npos);
  r = run("--check-config --input x --set power.config=" + std::string(SB_SOURCE_DIR) + "/config/power.json" +
          " --set slam.pipeline_config=" + std::string(SB_SOURCE_DIR) + "/config/pipeline.json" +
          " --set slam.controller_config=" + std::string(SB_SOURCE_DIR) + "/config/controller.json");
  INFO(r.output);
  CHECK(r.exitCode == 0);
}

TEST_CASE("slamboosterd: a power meter gives ENERGY per frame, energy.jsonl and STATUS joules", "[daemon][system]") {
  TempDir tmp;
  const std::string socket = tmp.path + "/s.sock", out = tmp.path + "/out";
  // A recorded constant 4.5 W at 200 Hz, replayed live by the "file" meter.
  constexpr double kWatts = 4.5;
  sb::test::writeConstantPowerMeter(tmp.path, kWatts);
  auto args = daemonArgs(socket, out, "recorded", "stop");
  // 4 s of input, so that the stream is still running when the client starts watching.
  args.insert(args.end(), {"--set", "power.config=" + tmp.path + "/power.json", "--set", "source.speed=0.25"});
  ChildProcess d(args, {}, tmp.path + "/log.txt");
  REQUIRE(sb::test::waitForPath(socket, 20));

  const auto watch = runCommand(kCtl + " --json --socket " + socket + " watch --count 3 --no-pose --no-knobs");
  INFO(watch.output << d.log());
  REQUIRE(watch.exitCode == 0);
  std::istringstream lines(watch.output);
  int energies = 0;
  for (std::string line; std::getline(lines, line);) {
    const json m = json::parse(line);
    REQUIRE(m["class"] == "ENERGY");
    CHECK(m["meter"] == "file");
    CHECK(m["joules"].get<double>() > 0.0);
    CHECK(m["mean_w"].get<double>() == Approx(kWatts).epsilon(1e-9));
    ++energies;
  }
  CHECK(energies == 3);
  const json status = ctlJson(socket, "status");
  CHECK(status["meter"] == "file");
  CHECK(status["energy"]["known_frames"].get<int>() >= 3);
  CHECK(status["energy"]["connected"] == true);

  d.signal(SIGTERM);
  REQUIRE(d.wait(30) == 0);
  // Every processed frame's energy is in energy.jsonl (the drain waits for the samples after the last frame),
  // each the constant power times the interval frames.jsonl logs for it.
  std::ifstream frames(out + "/frames.jsonl"), energy(out + "/energy.jsonl");
  size_t n = 0;
  for (std::string f, e; std::getline(frames, f) && std::getline(energy, e); ++n) {
    const json fj = json::parse(f), ej = json::parse(e);
    INFO("frame " << n);
    REQUIRE(ej["frame"] == fj["frame"]);
    REQUIRE(ej["known"] == true);
    const int64_t start = fj["t_start_mono_ns"], end = fj["t_end_mono_ns"];
    CHECK(ej["joules"].get<double>() == Approx(kWatts * (end - start) * 1e-9).epsilon(1e-9));
  }
  CHECK(n == dataLines(out + "/frames.jsonl"));
  CHECK(dataLines(out + "/energy.jsonl") == n);
  std::ifstream summaryFile(out + "/summary.json");
  const json summary = json::parse(summaryFile);
  CHECK(summary["energy"]["known_frames"].get<size_t>() == n);
  CHECK(summary["energy"]["meter"] == "file");
  CHECK(summary["energy"]["mean_watts"].get<double>() == Approx(kWatts).epsilon(1e-9));
  CHECK(fs::file_size(out + "/power.csv") > 0);
}
