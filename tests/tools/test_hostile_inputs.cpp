// `slambooster` against hostile or careless inputs (issue 33): nothing blocks on a FIFO (calibration.json,
// depth.txt, a depth PNG), messages say what a path really is (FIFO, directory, device, symlink loop) with
// control bytes escaped and long values cut, `bench --report-only` reports a bad summary and writes the rest,
// `synth` refuses absurd numbers up front, and the matrix options refuse impossible shards and indices.
// Every command runs under `timeout 20`: a blocking open would fail the test, not hang it.

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "tests/support/files.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

namespace fs = std::filesystem;
using sb::test::runCommand;

namespace {

const std::string kTool = SB_SLAMBOOSTER_BIN;
const std::string kRun = "timeout 20 " + kTool;

// A 6-frame 160x120 sequence, rendered once; copies of it are damaged by the tests.
const std::string& sequence() {
  static const std::string seq = [] {
    const std::string dir = sb::test::scratchDir("hostile_inputs_seq") + "/seq";
    const auto r = runCommand(kTool + " synth --out " + dir +
                              " --builtin-frames 6 --no-noise --width 160 --height 120 --fx 131 --fy 131");
    if (r.exitCode != 0) throw std::runtime_error("synth failed: " + r.output);
    return dir;
  }();
  return seq;
}

std::string copyOfSequence(const std::string& name) {
  const std::string dir = sb::test::scratchDir(name) + "/seq";
  fs::copy(sequence(), dir, fs::copy_options::recursive);
  return dir;
}

std::string firstPng(const std::string& seq) {
  std::vector<fs::path> pngs;
  for (const auto& e : fs::directory_iterator(seq + "/depth")) pngs.push_back(e.path());
  std::sort(pngs.begin(), pngs.end());
  return pngs.front().string();
}

// A refused input: exit 1 (not 124: a timeout, nor 3: an internal error), and the output says `needle`.
void checkRefused(const sb::test::CommandResult& r, const std::string& needle, const std::string& notSaid = "") {
  INFO(r.output.substr(0, 3000));
  CHECK(r.exitCode == 1);
  CHECK(r.output.find(needle) != std::string::npos);
  if (!notSaid.empty()) CHECK(r.output.find(notSaid) == std::string::npos);
  CHECK(r.output.find("internal error") == std::string::npos);
  CHECK(r.output.find('\x1b') == std::string::npos);  // no raw escape byte reaches the terminal
}

std::string runOn(const std::string& seq) { return kRun + " run " + seq + " --out " + seq + "-out --quiet"; }

}  // namespace

TEST_CASE("slambooster run: a FIFO as calibration.json, depth.txt or a depth PNG is refused, never waited on",
          "[tools][hostile]") {
  const std::string seq = copyOfSequence("hostile_fifo");
  fs::remove(seq + "/calibration.json");
  REQUIRE(::mkfifo((seq + "/calibration.json").c_str(), 0600) == 0);
  checkRefused(runCommand(runOn(seq)), "named pipe (FIFO)");
  fs::remove(seq + "/calibration.json");

  const std::string png = firstPng(seq);
  fs::remove(png);
  REQUIRE(::mkfifo(png.c_str(), 0600) == 0);
  checkRefused(runCommand(runOn(seq)), "named pipe (FIFO)", "does not exist");
  fs::remove(png);
  fs::create_directory(png);
  checkRefused(runCommand(runOn(seq)), "is a directory", "does not exist");
  fs::remove(png);

  const std::string index = seq + "/depth.txt";
  fs::rename(index, index + ".bak");
  REQUIRE(::mkfifo(index.c_str(), 0600) == 0);
  checkRefused(runCommand(runOn(seq)), "named pipe (FIFO)", "has no depth.txt");
  fs::remove(index);
  fs::create_directory(index);
  checkRefused(runCommand(runOn(seq)), "is a directory", "has no depth.txt");
  fs::remove(index);
  fs::create_symlink("/dev/zero", index);
  checkRefused(runCommand(runOn(seq)), "character device", "has no depth.txt");
  fs::remove(index);
  fs::rename(index + ".bak", index);
}

TEST_CASE("slambooster: messages say what a path is, escape control bytes and cut long values",
          "[tools][hostile]") {
  const std::string dir = sb::test::scratchDir("hostile_messages");
  // A symbolic-link loop is not "missing".
  fs::remove(dir + "/loop");
  fs::create_symlink(dir + "/loop", dir + "/loop");
  checkRefused(runCommand(kRun + " run " + dir + "/loop --out " + dir + "/o"), "symbolic-link loop",
               "does not exist");
  // A sequence in a directory its user cannot enter: "permission denied", not "does not exist". Root reads
  // everything, so as root the tool runs as nobody (uid 65534) on a directory of mode 0700.
  fs::create_directories(dir + "/locked");
  fs::copy(sequence(), dir + "/locked/seq", fs::copy_options::recursive);
  fs::permissions(dir + "/locked", fs::perms::owner_all);
  const std::string asOther = ::geteuid() == 0 ? "setpriv --reuid=65534 --regid=65534 --clear-groups " : "";
  if (::geteuid() != 0) fs::permissions(dir + "/locked", fs::perms::none);
  checkRefused(runCommand(asOther + kRun + " run " + dir + "/locked/seq --out /tmp/sb-hostile-never"),
               "permission denied", "does not exist");
  fs::permissions(dir + "/locked", fs::perms::owner_all);
  // eval on a directory: it is a directory, not a trajectory without poses.
  checkRefused(runCommand(kRun + " eval " + dir + " " + sequence() + "/groundtruth.txt"), "is a directory",
               "has no poses");
  // ESC and binary bytes from an input file are escaped; a 20 MB value does not become a 20 MB message.
  const std::string seq = copyOfSequence("hostile_bytes");
  std::ofstream(seq + "/depth.txt", std::ios::trunc) << "\x1b[2J\x1b[31m\x07garbage depth/x.png\n";
  const auto esc = runCommand(runOn(seq));
  checkRefused(esc, "\\x1b[2J");
  std::ofstream(seq + "/depth.txt", std::ios::trunc) << "1.0 " << std::string(20u << 20, 'a') << "\n";
  const auto huge = runCommand(runOn(seq));
  INFO(huge.output.size() << " bytes of output");
  CHECK(huge.exitCode == 1);
  CHECK(huge.output.size() < 20000);
}

TEST_CASE("slambooster synth: numeric options have ranges and clear errors", "[tools][hostile]") {
  const std::string dir = sb::test::scratchDir("hostile_synth");
  const std::string base = kRun + " synth --out " + dir + "/s --overwrite ";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--builtin-frames -1", "--builtin-frames"},
      {"--builtin-frames 1000000000", "--builtin-frames"},
      {"--builtin-frames 5 --width 100000", "--width"},
      {"--builtin-frames 5 --height 4097", "--height"},
      {"--builtin-frames 5 --fx nan", "--fx"},
      {"--builtin-frames 5 --fy inf", "--fy"},
      {"--builtin-frames 5 --cx nan", "--cx"},
      {"--builtin-frames 5 --noise-sigma nan", "--noise-sigma"},
      {"--builtin-frames 5 --min-depth nan", "--min-depth"}};
  for (const auto& [args, option] : cases) {
    const auto r = runCommand(base + args);
    INFO(args << ": " << r.output.substr(0, 2000));
    CHECK(r.exitCode == 2);  // a usage error, before anything is rendered
    CHECK(r.output.find(option) != std::string::npos);
    CHECK(r.output.find("internal error") == std::string::npos);
    CHECK_FALSE(fs::exists(dir + "/s/depth.txt"));
  }
}

TEST_CASE("slambooster bench: impossible shards and run indices are refused up front", "[tools][hostile]") {
  const std::string dir = sb::test::scratchDir("hostile_matrix");
  const std::string bench = kRun + " bench " + sequence() + " --out " + dir + "/b";
  for (const char* shard : {"0/0", "3/0", "0/-4", "-1/4", " 0/4"}) {
    const auto r = runCommand(bench + " --shard '" + shard + "'");
    INFO(shard << ": " << r.output);
    CHECK(r.exitCode == 2);
    CHECK(r.output.find("--shard") != std::string::npos);
  }
  for (const char* index : {"9223372036854775808", "18446744073709551615", "99999999999999999999999"}) {
    const auto r = runCommand(bench + " --run-index " + index);
    INFO(index << ": " << r.output);
    CHECK(r.exitCode == 2);
    CHECK(r.output.find("--run-index") != std::string::npos);
  }
  CHECK_FALSE(fs::exists(dir + "/b/runs"));  // nothing ran
}

TEST_CASE("slambooster bench --report-only: a bad summary is reported and left out, the rest reported",
          "[tools][hostile]") {
  const std::string dir = sb::test::scratchDir("hostile_bench");
  std::ofstream(dir + "/small.json") << R"({"volume_resolution": 64})";
  const std::string bench = kRun + " bench " + sequence() + " --out " + dir + "/b --config " + dir +
                            "/small.json --controllers default --threads 1 --quiet";
  const auto full = runCommand(bench);
  INFO(full.output.substr(0, 3000));
  REQUIRE(full.exitCode == 0);
  const std::string summary = dir + "/b/runs/seq/default/summary.json";
  nlohmann::json s = sb::test::readJson(summary);
  s["tracked_percent"] = "x";
  std::ofstream(summary, std::ios::trunc) << s.dump(2);
  const auto r = runCommand(bench + " --report-only");
  INFO(r.output.substr(0, 3000));
  CHECK(r.exitCode == 0);
  CHECK(r.output.find(summary) != std::string::npos);  // the file,
  CHECK(r.output.find("tracked_percent") != std::string::npos);  // the key
  CHECK(r.output.find("\"x\"") != std::string::npos);  // and the value
  const std::string md = sb::test::readText(dir + "/b/report.md");
  CHECK(md.find("Left out seq / default") != std::string::npos);
  const std::string csv = sb::test::readText(dir + "/b/results.csv");
  CHECK(csv.find("seq,accurate,") != std::string::npos);  // the rest is still reported
  CHECK(csv.find("seq,default,") == std::string::npos);
}
