// The adaptive controller end to end on a stress sequence with fast bursts (up to 1.15 m/s, past the paper's
// 0.035 m/frame correction threshold): the fast motion is tracked correctly, so adaptive must never replace
// it. The paper's `slambooster` on the same frames shows that the check sees a correction when one fires.
#include <catch2/catch.hpp>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "tests/support/files.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

using sb::test::readJson;
using sb::test::runCommand;

namespace {

const std::string kTool = SB_SLAMBOOSTER_BIN;

// Frames of the segments labelled `label` in segments.csv (label,begin_frame,end_frame).
std::set<long> segmentFrames(const std::string& path, const std::string& label) {
  std::ifstream in(path);
  std::set<long> frames;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string name, begin, end;
    std::getline(row, name, ',');
    std::getline(row, begin, ',');
    std::getline(row, end, ',');
    if (name == label)
      for (long f = std::stol(begin); f < std::stol(end); ++f) frames.insert(f);
  }
  return frames;
}

struct Corrections {
  size_t inSegment = 0, tracked = 0, frames = 0;
};

Corrections corrections(const std::string& framesPath, const std::set<long>& segment) {
  std::ifstream in(framesPath);
  Corrections c;
  for (std::string line; std::getline(in, line);) {
    const auto j = nlohmann::json::parse(line);
    if (!segment.count(j.at("frame").get<long>())) continue;
    ++c.frames;
    c.tracked += j.at("tracked").get<bool>();
    c.inSegment += j.at("corrected").get<bool>();
  }
  return c;
}

}  // namespace

TEST_CASE("adaptive does not correct fast motion that it tracks correctly", "[tools][adaptive][system]") {
  const std::string dir = sb::test::scratchDir("adaptive_bursts");
  const auto synth = runCommand(kTool + " synth --out " + dir + "/seq --scene livingroom --stress bursts --seed 0 " +
                                "--width 320 --height 240 --fx 240.6 --fy 240 --overwrite");
  INFO(synth.output);
  REQUIRE(synth.exitCode == 0);
  const std::set<long> bursts = segmentFrames(dir + "/seq/segments.csv", "burst");
  REQUIRE(bursts.size() >= 40);

  const auto adaptive = runCommand(kTool + " run " + dir + "/seq --out " + dir + "/adaptive --controller adaptive --quiet");
  INFO(adaptive.output);
  REQUIRE(adaptive.exitCode == 0);
  const Corrections a = corrections(dir + "/adaptive/frames.jsonl", bursts);
  CHECK(a.frames == bursts.size());
  CHECK(a.tracked == a.frames);
  CHECK(a.inSegment == 0);
  const auto summary = readJson(dir + "/adaptive/summary.json");
  CHECK(summary.at("corrected") == 0);
  CHECK(summary.at("ate").at("rmse_m").get<double>() < 0.02);

  // The paper's controller replaces poses of the same bursts (its velocity threshold): the check can fail.
  const auto paper = runCommand(kTool + " run " + dir + "/seq --out " + dir + "/slambooster --controller slambooster --quiet");
  REQUIRE(paper.exitCode == 0);
  CHECK(corrections(dir + "/slambooster/frames.jsonl", bursts).inSegment > 0);
}
