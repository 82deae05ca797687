// slamboosterd when its input fails mid-pass (issue 33): a truncated PNG in the middle of the sequence. The
// pass is never reported complete: summary.json says "complete": false with the error, STATUS says "failed"
// (and source.state "failed"), and the daemon exits 1 (at once with at_end exit, at SIGTERM otherwise).

#include <signal.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "tests/daemon/daemon_e2e.h"
#include "tests/daemon/process.h"
#include "tests/support/files.h"

using nlohmann::json;
using sb::test::ChildProcess;
using namespace sb::test::e2e;

namespace {

constexpr size_t kBadFrame = 12;

// The fixture sequence with frame kBadFrame's PNG cut to 100 bytes; returns the copy's directory.
std::string sequenceWithTruncatedFrame(const std::string& dir, std::string& badPng) {
  const std::string seq = dir + "/seq";
  std::filesystem::copy(fixture().sequence, seq, std::filesystem::copy_options::recursive);
  std::vector<std::filesystem::path> depth;
  for (const auto& e : std::filesystem::directory_iterator(seq + "/depth")) depth.push_back(e.path());
  std::sort(depth.begin(), depth.end());
  REQUIRE(depth.size() > kBadFrame + 5);
  std::filesystem::resize_file(depth[kBadFrame], 100);
  badPng = depth[kBadFrame].filename().string();
  return seq;
}

std::vector<std::string> argsFor(const std::string& seq, const std::string& socket, const std::string& out,
                                 const std::string& pacing, const std::string& atEnd) {
  auto args = daemonArgs(socket, out, pacing, atEnd);
  args[2] = seq;  // --input
  return args;
}

void checkSummaryFailed(const std::string& out, const std::string& badPng) {
  const json summary = sb::test::readJson(out + "/summary.json");
  INFO(summary.dump(1).substr(0, 2000));
  CHECK(summary["complete"] == false);
  REQUIRE(summary.contains("error"));
  CHECK(summary["error"].get<std::string>().find(badPng) != std::string::npos);
  CHECK(summary["frames"].get<size_t>() == kBadFrame);
  CHECK(dataLines(out + "/trajectory.tum") == kBadFrame);
}

}  // namespace

TEST_CASE("slamboosterd: a truncated PNG mid-pass is not reported complete (at_end exit)", "[daemon][system]") {
  TempDir tmp;
  std::string badPng;
  const std::string seq = sequenceWithTruncatedFrame(tmp.path, badPng);
  const std::string out = tmp.path + "/out";
  ChildProcess daemon(argsFor(seq, tmp.path + "/s.sock", out, "fast", "exit"), {}, tmp.path + "/daemon.log");
  const int code = daemon.wait(60);
  INFO(daemon.log());
  CHECK(code == 1);
  checkSummaryFailed(out, badPng);
}

TEST_CASE("slamboosterd: STATUS says failed, with the error, after a truncated PNG (at_end loop)",
          "[daemon][system]") {
  TempDir tmp;
  std::string badPng;
  const std::string seq = sequenceWithTruncatedFrame(tmp.path, badPng);
  const std::string socket = tmp.path + "/s.sock", out = tmp.path + "/out";
  ChildProcess daemon(argsFor(seq, socket, out, "fast", "loop"), {}, tmp.path + "/daemon.log");
  REQUIRE(sb::test::waitForPath(socket, 20));
  json status;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (std::chrono::steady_clock::now() < deadline) {
    // The socket file exists a moment before the daemon listens: a refused connection is retried.
    const auto r = sb::test::runCommand(kCtl + " --json --socket " + socket + " status");
    if (r.exitCode == 0) {
      status = json::parse(r.output.substr(0, r.output.find('\n')));
      if (status["state"] != "running" && status["state"] != "starting") break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  INFO(status.dump(1));
  CHECK(status["state"] == "failed");
  CHECK(status["source"]["state"] == "failed");
  REQUIRE(status.contains("error"));
  CHECK(status["error"].get<std::string>().find(badPng) != std::string::npos);
  checkSummaryFailed(out + "/pass-0001", badPng);
  daemon.signal(SIGTERM);
  INFO(daemon.log());
  CHECK(daemon.wait(30) == 1);
}
