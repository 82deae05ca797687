// Issue 53's findings at `slambooster run`, as a user runs it (the fourth round of attacks, on 1121ad2):
// an odometry file's memory grew with its length (about 920 B a sample: 10^6 lines took 1.06 GB, 10^7 ended
// in std::bad_alloc), and `--map-mount 1.2,nan,0` was accepted (rc 0, a 0x0 map.pgm, null in map_frame.json).
// Run against another build with SB_TEST_SLAMBOOSTER=.../slambooster.
#include <catch2/catch.hpp>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>

#include "tests/support/files.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

using sb::test::runCommand;

namespace {

const std::string kTool = sb::test::testBinary("SB_TEST_SLAMBOOSTER", SB_SLAMBOOSTER_BIN);

// This program's scratch directory (scratchDir empties it: called once).
const std::string& root() {
  static const std::string dir = sb::test::scratchDir("odometry_map_doors");
  return dir;
}

// A short drive (20 frames, 160x120) with its odometry.txt, rendered once.
const std::string& drive() {
  static const std::string sequence = [] {
    const std::string dir = root() + "/drive";
    const auto synth = runCommand(kTool + " synth --scene corridor --stress drive --seed 1 --frames 20 --width 160 " +
                                  "--height 120 --fx 120 --fy 120 --threads 1 --overwrite --out " + dir);
    if (synth.exitCode != 0) throw std::runtime_error("synth failed: " + synth.output);
    return dir;
  }();
  return sequence;
}

// The drive's odometry.txt followed by samples at 100 Hz after its last, `lines` in all.
std::string longOdometry(size_t lines) {
  const std::string path = root() + "/odometry-" + std::to_string(lines) + ".txt";
  std::ifstream in(drive() + "/odometry.txt");
  std::ofstream out(path);
  out << std::fixed << std::setprecision(6);
  size_t n = 0;
  double last = 0.0;
  std::string lastPose;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    out << line << "\n";
    ++n;
    std::istringstream ss(line);
    ss >> last;
    std::getline(ss, lastPose);
  }
  for (; n < lines; ++n) {
    last += 0.01;
    out << last << lastPose << "\n";
  }
  return path;
}

// Peak resident memory (kB) of `slambooster run` of the drive with `odometry`.
long peakKb(const std::string& odometry, const std::string& out) {
  const auto r = runCommand("/usr/bin/time -f 'peak-kb %M' " + kTool + " run " + drive() + " --out " + out +
                            " --odometry " + odometry + " --controller fixed --threads 1 --quiet 2>&1");
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  const auto at = r.output.rfind("peak-kb ");
  REQUIRE(at != std::string::npos);
  return std::stol(r.output.substr(at + 8));
}

}  // namespace

TEST_CASE("an odometry file's length does not grow the run's memory", "[cli][odometry][issue53]") {
  const std::string& dir = root();
  const long small = peakKb(longOdometry(100000), dir + "/small");
  const long large = peakKb(longOdometry(1000000), dir + "/large");
  INFO("peak RSS with 10^5 lines " << small << " kB, with 10^6 lines " << large << " kB");
  // Held whole, the 900,000 more samples took about 800 MB more; read as the frames need them, nothing more.
  CHECK(large - small < 20 * 1024);
  // The odometry was used: the summary counts the frames it covered.
  const auto summary = sb::test::readJson(dir + "/large/summary.json");
  CHECK(summary.at("odometry").at("frames_with_pose").get<int>() >= 18);
}

TEST_CASE("--map-mount: nan, inf and out-of-range values are refused naming the option", "[cli][navmap][issue53]") {
  const std::string& dir = root();
  for (const std::string mount : {"1.2,nan,0", "1.2,0,nan", "nan,0,0", "1.2,inf,0", "1.2,0,1e300", "1.2,100,0",
                                  "1e300,0,0", "1.2,0x,0"}) {
    INFO(mount);
    const auto r = runCommand(kTool + " run " + drive() + " --out " + dir + "/mount --controller fixed --threads 1 " +
                              "--quiet --no-odometry --map-mount " + mount + " 2>&1");
    INFO(r.output);
    CHECK(r.exitCode != 0);
    CHECK(r.output.find("--map-mount") != std::string::npos);
  }
  // A sane mount still makes a map.
  const auto ok = runCommand(kTool + " run " + drive() + " --out " + dir + "/mount-ok --controller fixed --threads 1 " +
                             "--quiet --no-odometry --map-mount 0.5,10,0 2>&1");
  INFO(ok.output);
  CHECK(ok.exitCode == 0);
}
