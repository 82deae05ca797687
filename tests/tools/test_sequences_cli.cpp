// The long-run test sequences made as a user makes them (`slambooster synth`, `slambooster cut`): a small
// synthetic kidnap whose covered frames have no depth, a short corridor drive whose volume hint holds the
// path, a cut with a jump back that re-reads frame for frame, and the scene / stress mismatches refused.
#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "drivers/sequence.h"
#include "tests/support/files.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

using sb::test::readJson;
using sb::test::runCommand;

namespace {

const std::string kTool = SB_SLAMBOOSTER_BIN;
// ICL-NUIM's camera at 1/8 resolution: the same view, quick to render.
const std::string kSmall = " --width 80 --height 60 --fx 60.15 --fy 60 --overwrite";

struct Segment {
  std::string label;
  size_t begin = 0, end = 0;
};

std::vector<Segment> readSegments(const std::string& path) {
  std::ifstream in(path);
  std::vector<Segment> out;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::stringstream row(line);
    Segment s;
    std::string begin, end;
    std::getline(row, s.label, ',');
    std::getline(row, begin, ',');
    std::getline(row, end, ',');
    s.begin = std::stoul(begin);
    s.end = std::stoul(end);
    out.push_back(s);
  }
  return out;
}

size_t validPixels(const sb::DepthFrame& f) {
  size_t n = 0;
  for (uint16_t v : f.depth.pixels()) n += v != 0;
  return n;
}

}  // namespace

TEST_CASE("synth kidnap: covered frames without depth; cut makes a jump back from it",
          "[tools][sequences][system]") {
  const std::string dir = sb::test::scratchDir("sequences_kidnap");
  const auto synth = runCommand(kTool + " synth --out " + dir + "/kidnap --stress kidnap --seed 2" + kSmall);
  INFO(synth.output);
  REQUIRE(synth.exitCode == 0);
  const std::vector<Segment> segments = readSegments(dir + "/kidnap/segments.csv");
  REQUIRE(segments.size() == 3);
  CHECK(segments[0].label == "mapping");
  REQUIRE(segments[1].label == "covered");
  CHECK(segments[2].label == "after");
  {
    auto seq = sb::openSequence(dir + "/kidnap");
    for (size_t i = 0; i < segments[2].end; ++i) {
      const auto f = seq->next();
      REQUIRE(f);
      INFO("frame " << i);
      if (i >= segments[1].begin && i < segments[1].end)
        REQUIRE(validPixels(*f) == 0);
      else
        REQUIRE(validPixels(*f) > f->depth.size() / 2);
    }
  }

  const auto cut = runCommand(kTool + " cut " + dir + "/kidnap --frames 0-99,10-19 --out " + dir + "/cut");
  INFO(cut.output);
  REQUIRE(cut.exitCode == 0);
  CHECK(cut.output.find("jump at frame 100 (source 99 -> 10)") != std::string::npos);
  auto original = sb::openSequence(dir + "/kidnap");
  std::vector<sb::DepthFrame> frames;
  while (auto f = original->next()) frames.push_back(std::move(*f));
  auto seq = sb::openSequence(dir + "/cut");
  REQUIRE(seq->info().frameCount == 110);
  for (size_t k = 0; k < 110; ++k) {
    const auto f = seq->next();
    REQUIRE(f);
    CHECK(f->timestamp == Approx(k / 30.0).margin(1e-5));
    CHECK(f->depth.pixels() == frames.at(k < 100 ? k : k - 90).depth.pixels());
  }
}

TEST_CASE("synth drive: a corridor drive whose volume hint holds the path", "[tools][sequences][system]") {
  const std::string dir = sb::test::scratchDir("sequences_drive");
  const auto synth = runCommand(kTool + " synth --out " + dir +
                                "/drive --scene corridor --corridor-length 8 "
                                "--stress drive --seed 1" +
                                kSmall);
  INFO(synth.output);
  REQUIRE(synth.exitCode == 0);
  const auto calibration = readJson(dir + "/drive/calibration.json");
  CHECK(calibration.at("volume_size_m").get<double>() >= 8.0);
  const std::vector<Segment> segments = readSegments(dir + "/drive/segments.csv");
  REQUIRE(segments.size() == 7);
  CHECK(segments[3].label == "turn");

  for (const char* wrong : {" --stress drive", " --scene corridor --stress kidnap"}) {
    const auto bad = runCommand(kTool + " synth --out " + dir + "/bad" + wrong + kSmall);
    INFO(wrong << ": " << bad.output);
    CHECK(bad.exitCode == 1);
    CHECK(bad.output.find("--stress drive runs in --scene corridor") != std::string::npos);
  }
}
