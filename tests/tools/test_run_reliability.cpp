// `slambooster run` and slamboosterd when things go wrong (issue 23): SIGTERM and Ctrl-C finish the frame
// in hand and write every output; a full disk stops the run at the first failed write with the files
// consistent; a bad frame still leaves a summary; and SIGKILL at random moments leaves every output a
// line-complete prefix of the run, the files agreeing within one frame.

#include <signal.h>
#include <sys/mount.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <sstream>
#include <thread>

#include "tests/daemon/process.h"
#include "tests/support/constant_power.h"
#include "tests/support/files.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

namespace fs = std::filesystem;
using nlohmann::json;
using sb::test::ChildProcess;
using sb::test::runCommand;

namespace {

const std::string kTool = SB_SLAMBOOSTER_BIN;
const std::string kDaemon = SB_SLAMBOOSTERD_BIN;
constexpr int kFrames = 60;

// A synthetic sequence of kFrames frames (320x240, 64^3 volume: tens of ms per frame), rendered once.
struct Sequence {
  std::string dir, path, config;
  Sequence() {
    dir = sb::test::scratchDir("run_reliability_seq");
    path = dir + "/seq";
    const auto r =
        runCommand(kTool + " synth --out " + path + " --builtin-frames " + std::to_string(kFrames) +
                   " --width 320 --height 240 --fx 240 --fy 240 --threads 1");
    if (r.exitCode != 0) throw std::runtime_error("synth failed: " + r.output);
    config = dir + "/pipeline.json";
    std::ofstream(config) << R"({"volume_resolution": 64, "knobs": "csr=2,ir=1"})";
  }
};

const Sequence& sequence() {
  static const Sequence s;
  return s;
}

std::vector<std::string> runArgs(const std::string& out) {
  return {kTool,       "run", sequence().path, "--out", out, "--config", sequence().config,
          "--threads", "1",   "--quiet"};
}

// Lines of a file that must consist of whole lines (every line ends in '\n'); data lines only.
size_t wholeLines(const std::string& path, bool jsonLines) {
  if (!fs::exists(path)) return 0;
  const std::string text = sb::test::readText(path);
  INFO(path);
  CHECK((text.empty() || text.back() == '\n'));
  std::istringstream in(text);
  size_t n = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    if (jsonLines) {
      INFO(line.substr(0, 200));
      CHECK(json::parse(line, nullptr, false).is_object());
    } else {
      std::istringstream fields(line);
      double v;
      int count = 0;
      while (fields >> v) ++count;
      CHECK(count == 8);
    }
    ++n;
  }
  return n;
}

// '\n' bytes in a file being written (no checks: it may end in part of a line while the writer runs).
size_t newlines(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return static_cast<size_t>(std::count(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>(), '\n'));
}

struct Counts {
  size_t trajectory = 0, frames = 0;
  std::optional<size_t> summary;  // absent before the first frame
};

// Reads the outputs in `out` and checks that they are line-complete and agree within one frame.
Counts checkConsistent(const std::string& out) {
  Counts c;
  c.trajectory = wholeLines(out + "/trajectory.tum", false);
  c.frames = wholeLines(out + "/frames.jsonl", true);
  if (fs::exists(out + "/summary.json")) {
    const json s = json::parse(sb::test::readText(out + "/summary.json"), nullptr, false);
    REQUIRE(s.is_object());
    c.summary = s["frames"].get<size_t>();
  }
  INFO("trajectory " << c.trajectory << ", frames.jsonl " << c.frames << ", summary "
                     << (c.summary ? std::to_string(*c.summary) : "absent"));
  CHECK(c.trajectory <= c.frames + 1);
  CHECK(c.frames <= c.trajectory);
  if (c.summary) {
    CHECK(*c.summary + 1 >= c.trajectory);
    CHECK(*c.summary <= c.trajectory);
  } else {
    CHECK(c.trajectory <= 1);
  }
  return c;
}

}  // namespace

TEST_CASE("slambooster run: SIGTERM and SIGINT finish the frame in hand and write every output",
          "[tools][run]") {
  for (const int sig : {SIGTERM, SIGINT}) {
    const std::string out = sb::test::scratchDir("run_signal_" + std::to_string(sig));
    ChildProcess run(runArgs(out), {}, out + ".log");
    // Signal once a few frames are on disk.
    for (int i = 0; i < 600 && wholeLines(out + "/frames.jsonl", true) < 5; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    run.signal(sig);
    const int rc = run.wait(60);
    INFO(run.log());
    CHECK(rc == 128 + sig);
    CHECK(run.log().find("interrupted by") != std::string::npos);
    const Counts c = checkConsistent(out);
    CHECK(c.trajectory == c.frames);
    REQUIRE(c.summary);
    CHECK(*c.summary == c.trajectory);
    CHECK(c.trajectory >= 5);
    CHECK(c.trajectory < static_cast<size_t>(kFrames));
    const json summary = sb::test::readJson(out + "/summary.json");
    CHECK(summary["complete"] == false);
    CHECK(summary["interrupted"]["signal"] == (sig == SIGTERM ? "SIGTERM" : "SIGINT"));
  }
}

TEST_CASE("slambooster run: a full disk stops the run at the first failed write, files consistent",
          "[tools][run]") {
  const std::string dir =
      fs::path(sb::test::scratchDir("run_disk_full_probe")).parent_path() / "run_disk_full";
  ::umount2((dir + "/out").c_str(), MNT_DETACH);  // left over from a test run that was killed
  const std::string out = sb::test::scratchDir("run_disk_full") + "/out";
  fs::create_directories(out);
  if (::mount("tmpfs", out.c_str(), "tmpfs", 0, "size=48k") != 0) {
    WARN("cannot mount a 48 KiB tmpfs (needs root): skipped");
    return;
  }
  struct Unmount {
    std::string path;
    ~Unmount() { ::umount2(path.c_str(), MNT_DETACH); }
  } unmount{out};
  std::string args;
  for (const auto& a : runArgs(out)) args += a + " ";
  const auto r = runCommand(args);
  INFO(r.output);
  CHECK(r.exitCode == 1);
  CHECK(r.output.find("No space left on device") != std::string::npos);
  CHECK(r.output.find(out) != std::string::npos);  // the error names the file
  const Counts c = checkConsistent(out);
  CHECK(c.trajectory > 0);
  CHECK(c.trajectory < static_cast<size_t>(kFrames));  // stopped at the first failed write
}

TEST_CASE("slambooster run: a full disk at the end leaves no truncated model.png and still a summary",
          "[tools][run]") {
  // Issue 33: every frame's outputs fit, model.png does not. It used to leave a truncated model.png, say
  // "Write Error" without the reason, and never write the final summary.
  const std::string reference = sb::test::scratchDir("run_end_full_reference") + "/out";
  std::string args;
  for (const auto& a : runArgs(reference)) args += a + " ";
  REQUIRE(runCommand(args).exitCode == 0);
  const auto pages = [](uintmax_t bytes) { return (bytes + 4095) / 4096 * 4096; };
  const uintmax_t model = fs::file_size(reference + "/model.png");
  // Room for the per-frame files and two summaries (the new one is written beside the old, then renamed),
  // with a page of slack for the longer final summary; model.png must not fit in what is left.
  const uintmax_t summaryBytes = pages(fs::file_size(reference + "/summary.json") + 2048);
  // And the room the run keeps aside from its start for its last summary (runtime/summary_sink.h: 16 KiB,
  // kSummaryReserveBytes, or twice the largest summary; issue 53 finding 8).
  const uintmax_t reserveBytes =
      pages(std::max<uintmax_t>(16 << 10, 2 * fs::file_size(reference + "/summary.json")));
  const uintmax_t room = pages(fs::file_size(reference + "/trajectory.tum")) +
                         pages(fs::file_size(reference + "/frames.jsonl")) + 2 * summaryBytes + reserveBytes +
                         4096;
  // What is left for model.png is under room - (per-frame files) + one page of rounding.
  REQUIRE(model > 2 * summaryBytes + 2 * 4096);  // else the disk cannot be sized between the two
  const std::string dir =
      fs::path(sb::test::scratchDir("run_end_full_probe")).parent_path() / "run_end_full";
  ::umount2(dir.c_str(), MNT_DETACH);  // left over from a test run that was killed
  fs::create_directories(dir);
  const uintmax_t disk = 1u << 20;
  if (::mount("tmpfs", dir.c_str(), "tmpfs", 0, ("size=" + std::to_string(disk)).c_str()) != 0) {
    WARN("cannot mount a 1 MiB tmpfs (needs root): skipped");
    return;
  }
  struct Unmount {
    std::string path;
    ~Unmount() { ::umount2(path.c_str(), MNT_DETACH); }
  } unmount{dir};
  {
    std::ofstream filler(dir + "/filler", std::ios::binary);
    const std::string block(4096, '\0');
    for (uintmax_t n = 0; n + room < disk; n += block.size()) filler << block;
  }
  const std::string out = dir + "/out";
  args.clear();
  for (const auto& a : runArgs(out)) args += a + " ";
  const auto r = runCommand(args);
  INFO(r.output);
  CHECK(r.exitCode == 1);
  CHECK(r.output.find("model.png") != std::string::npos);  // the message names the file
  CHECK(r.output.find("No space left on device") != std::string::npos);  // and the system's reason
  CHECK_FALSE(fs::exists(out + "/model.png"));  // no truncated file under the real name
  CHECK_FALSE(fs::exists(out + "/model.png.tmp"));
  const Counts c = checkConsistent(out);
  CHECK(c.trajectory == static_cast<size_t>(kFrames));  // every frame ran and was written
  REQUIRE(c.summary);
  CHECK(*c.summary == static_cast<size_t>(kFrames));
  const json summary = sb::test::readJson(out + "/summary.json");
  CHECK(summary["complete"] == false);
  REQUIRE(summary.contains("error"));
  CHECK(summary["error"].get<std::string>().find("model.png") != std::string::npos);
  CHECK(summary.contains("ate"));  // the final summary, not a per-frame snapshot
}

TEST_CASE("slambooster run: a bad frame mid-sequence still leaves a summary of the frames before it",
          "[tools][run]") {
  const std::string dir = sb::test::scratchDir("run_bad_frame");
  fs::copy(sequence().path, dir + "/seq", fs::copy_options::recursive);
  std::vector<fs::path> depth;
  for (const auto& e : fs::directory_iterator(dir + "/seq/depth")) depth.push_back(e.path());
  std::sort(depth.begin(), depth.end());
  REQUIRE(depth.size() > 20);
  fs::resize_file(depth[20], 100);  // frame 20: a truncated PNG
  const std::string out = dir + "/out";
  const auto r = runCommand(kTool + " run " + dir + "/seq --out " + out + " --config " + sequence().config +
                            " --threads 1 --quiet");
  INFO(r.output);
  CHECK(r.exitCode == 1);
  const Counts c = checkConsistent(out);
  REQUIRE(c.summary);
  CHECK(*c.summary == c.trajectory);
  const json summary = sb::test::readJson(out + "/summary.json");
  CHECK(summary["complete"] == false);
  CHECK(summary.contains("error"));
}

TEST_CASE("SIGKILL at 20 random moments: outputs are line-complete and agree within one frame",
          "[tools][run][daemon]") {
  std::mt19937 rng(2323);
  const std::string dir = sb::test::scratchDir("run_sigkill");
  const std::string power = sb::test::writeConstantPowerMeter(dir, 4.0);  // energy.jsonl too
  for (const bool daemon : {false, true}) {
    const auto args = [&](const std::string& out, int i) {
      if (!daemon) {
        auto a = runArgs(out);
        a.insert(a.end(), {"--power", power});
        return a;
      }
      return std::vector<std::string>{kDaemon, "--input", sequence().path, "--out", out, "--socket",
                                      dir + "/s" + std::to_string(i), "--pacing", "fast", "--at-end", "exit",
                                      "--controller", "fixed", "--cpus", "all", "--set",
                                      "slam.pipeline_config=" + sequence().config, "--set", "slam.threads=1",
                                      "--set", "output.report=false", "--set", "power.config=" + power};
    };
    // A whole run first: the kills land at random moments within its duration.
    const auto start = std::chrono::steady_clock::now();
    {
      ChildProcess whole(args(dir + "/whole", 99), {}, dir + "/whole.log");
      INFO(whole.log());
      REQUIRE(whole.wait(120) == 0);
    }
    const auto wholeMs = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - start);
    REQUIRE(checkConsistent(dir + "/whole").trajectory == static_cast<size_t>(kFrames));
    int midRun = 0;
    for (int i = 0; i < 20; ++i) {
      const std::string out = dir + "/" + (daemon ? "d" : "r") + std::to_string(i);
      ChildProcess p(args(out, i), {}, out + ".log");
      int ms = static_cast<int>(rng() % static_cast<unsigned>(wholeMs.count() + 1));
      if (i % 2 == 0) {
        std::this_thread::sleep_for(std::chrono::milliseconds(ms));
      } else {  // every other kill once a random number of frames is logged (start-up is a good part of a run)
        const size_t target = 1 + rng() % (kFrames - 2);
        const auto t0 = std::chrono::steady_clock::now();
        while (newlines(out + "/frames.jsonl") < target && std::chrono::steady_clock::now() - t0 < wholeMs * 4)
          std::this_thread::sleep_for(std::chrono::milliseconds(1));
        ms = static_cast<int>(
            std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0).count());
      }
      p.signal(SIGKILL);
      p.wait(10);
      INFO((daemon ? "slamboosterd" : "slambooster run") << " killed after " << ms << " of " << wholeMs.count()
                                                          << " ms");
      const Counts c = checkConsistent(out);
      CHECK(wholeLines(out + "/energy.jsonl", true) <= c.trajectory);  // whole lines; energy follows its frame
      midRun += c.trajectory > 0 && c.trajectory < static_cast<size_t>(kFrames);
    }
    INFO((daemon ? "slamboosterd" : "slambooster run") << ": " << midRun << " of 20 kills landed mid-run");
    CHECK(midRun >= 8);  // the test is not vacuous
  }
}
