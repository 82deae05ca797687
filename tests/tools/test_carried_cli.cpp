// The kidnapped robot at `slambooster run` (issue 52 item 2), as a user runs it: a corridor drive at 320x240 whose
// robot is picked up and set down metres back along the corridor, at a place it mapped earlier and that has left
// the 5 m moving volume (synth --odom-carried: the wheels say nothing of the carry). The fault watch goes `lost`;
// before, every keyframe candidate at the set-down place lay outside the volume, ICP found nothing there (best
// agreement 0.00) and the run stayed lost until the robot drove back into the volume. Now the slabs that left the
// volume are kept in memory (relocalise_kept_map_mib) and the volume is placed for each candidate from them: the run
// relocalises soon after it is lost, and no `good` frame lies.
//
// The control run keeps nothing (relocalise_kept_map_mib 0): it must not relocalise in the same time, or this test
// would show nothing.
//
// A second drive is carried in the middle of its U-turn: set down facing along the corridor while the wheels' pose
// faces the turn's side, the model there covering less of the view than usual and agreeing with none of it. That
// was no evidence of a kidnap, the dispute waited for the wheels' 3 m budget, and the run was lost to its end (a
// held-out drive like it drove on into unmapped space and lied 336 frames). The bar is issue 52's: relocalised within
// 2 s of the set-down, 10 cm over the frames after it.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>

#include "core/trajectory.h"
#include "tests/support/anchored_frames.h"
#include "tests/support/files.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

using sb::test::runCommand;

namespace {

const std::string kTool = sb::test::testBinary("SB_TEST_SLAMBOOSTER", SB_SLAMBOOSTER_BIN);
constexpr int kSeed = 24;
constexpr double kCarriedAtS = 15.3, kBackM = 9.0;
constexpr int kFrames = 630;
constexpr double kRelocaliseWithinS = 2.0;  // from the first lost frame
constexpr double kOffM = 0.5;               // a `good` frame farther than this from the truth is a lie

struct Verdict {
  std::optional<double> firstLostS, relocalisedS;  // the first lost frame, the first relocalised one after it
  int frames = 0, lost = 0, goodOff = 0;
  double worstGoodAfterM = 0.0;  // the worst `good` frame after the set-down
  int posedAfter = 0;            // frames posed (not lost) from the relocalisation on ...
  double sumSquaresAfter = 0.0;  // ... and their squared errors
  nlohmann::json map;            // summary.json's "map_store"
  double ateAfterM() const { return posedAfter > 0 ? std::sqrt(sumSquaresAfter / posedAfter) : INFINITY; }
};

// The run's frames against the truth, both anchored at the first frame's whole pose (a robot's map frame: no
// alignment; tests/support/anchored_frames.h); the carry at `carriedAtS`.
Verdict judge(const std::string& run, const sb::Trajectory& truth, double carriedAtS) {
  Verdict v;
  for (const sb::test::AnchoredFrame& f : sb::test::anchoredFrames(run, truth)) {
    const double t = f.timestamp;
    ++v.frames;
    v.lost += f.state == "lost";
    if (f.state == "lost" && !v.firstLostS) v.firstLostS = t;
    if (f.state == "relocalised" && v.firstLostS && !v.relocalisedS) v.relocalisedS = t;
    if (f.state == "good") {
      v.goodOff += f.errorM > kOffM;
      if (t >= carriedAtS) v.worstGoodAfterM = std::max(v.worstGoodAfterM, f.errorM);
    }
    if (v.relocalisedS && f.state != "lost") {
      ++v.posedAfter;
      v.sumSquaresAfter += f.errorM * f.errorM;
    }
  }
  std::ifstream summary(run + "/summary.json");
  const auto s = nlohmann::json::parse(summary);
  if (s.contains("map_store")) v.map = s["map_store"];
  return v;
}

// A 320x240 corridor drive of `frames` frames in `dir`/drive whose robot is carried at `atS` seconds `backM` metres
// back along its path; its truth.
sb::Trajectory synthCarried(const std::string& dir, int seed, int frames, double atS, double backM) {
  char carried[64];
  std::snprintf(carried, sizeof carried, " --odom-carried %.1f,%.1f", atS, backM);
  const auto synth = runCommand(kTool + " synth --out " + dir + "/drive --scene corridor --stress drive --seed " +
                                std::to_string(seed) + " --frames " + std::to_string(frames) +
                                " --width 320 --height 240 --fx 240.6 --fy 240 --threads 1 --overwrite" + carried);
  INFO(synth.output);
  REQUIRE(synth.exitCode == 0);
  sb::Trajectory truth = sb::readTumTrajectory(dir + "/drive/groundtruth.txt");
  REQUIRE(truth.size() == size_t(frames));
  return truth;
}

std::set<std::string> files(const std::string& dir) {
  std::set<std::string> names;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    names.insert(std::filesystem::relative(e.path(), dir).string());
  return names;
}

}  // namespace

TEST_CASE("a robot carried back along the corridor relocalises on the map that left the volume",
          "[reloc][system]") {
  const std::string dir = sb::test::scratchDir("test_carried_cli");
  const sb::Trajectory truth = synthCarried(dir, kSeed, kFrames, kCarriedAtS, kBackM);
  const std::string knobs = " --controller default --threads 1 --quiet";

  const auto kept = runCommand(kTool + " run " + dir + "/drive --out " + dir + "/kept" + knobs);
  INFO(kept.output);
  REQUIRE(kept.exitCode == 0);
  const Verdict with = judge(dir + "/kept", truth, kCarriedAtS);
  INFO("kept: first lost " << with.firstLostS.value_or(-1) << " s, relocalised " << with.relocalisedS.value_or(-1)
                           << " s, lost frames " << with.lost << " of " << with.frames << ", worst good after the "
                           << "set-down " << with.worstGoodAfterM << " m, map " << with.map.dump());
  REQUIRE(with.firstLostS);
  CHECK(*with.firstLostS > kCarriedAtS);  // the fault watch's part: lost after the carry, not before
  REQUIRE(with.relocalisedS);
  CHECK(*with.relocalisedS - *with.firstLostS <= kRelocaliseWithinS);
  CHECK(with.goodOff == 0);
  CHECK(with.map.value("in_memory", false));
  CHECK(with.map.value("placements", 0) > 0);

  std::ofstream(dir + "/volume_only.json") << R"({"relocalise_kept_map_mib": 0})";
  const auto volume = runCommand(kTool + " run " + dir + "/drive --out " + dir + "/volume --config " + dir +
                                 "/volume_only.json" + knobs);
  INFO(volume.output);
  REQUIRE(volume.exitCode == 0);
  const Verdict without = judge(dir + "/volume", truth, kCarriedAtS);
  INFO("volume only: first lost " << without.firstLostS.value_or(-1) << " s, relocalised "
                                  << without.relocalisedS.value_or(-1) << " s");
  REQUIRE(without.firstLostS);
  CHECK((!without.relocalisedS || *without.relocalisedS - *without.firstLostS > kRelocaliseWithinS));
  CHECK(without.goodOff == 0);
  CHECK(without.map.is_null());
  // The kept slabs are in memory only: the run's directory holds the files of a run that keeps none.
  CHECK(files(dir + "/kept") == files(dir + "/volume"));
}

TEST_CASE("a robot carried back in the middle of its U-turn is found kidnapped and relocalised within 2 s",
          "[reloc][system]") {
  const std::string dir = sb::test::scratchDir("test_carried_cli_turn");
  constexpr int kTurnSeed = 57, kTurnFrames = 660;  // the U-turn from frame 429 (14.3 s)
  constexpr double kTurnCarriedAtS = 17.5, kTurnBackM = 8.0;
  constexpr double kSetDownWithinS = 2.0, kAteAfterM = 0.10;
  const sb::Trajectory truth = synthCarried(dir, kTurnSeed, kTurnFrames, kTurnCarriedAtS, kTurnBackM);
  const auto run = runCommand(kTool + " run " + dir + "/drive --out " + dir + "/run --controller default "
                              "--threads 1 --quiet");
  INFO(run.output);
  REQUIRE(run.exitCode == 0);
  const Verdict v = judge(dir + "/run", truth, kTurnCarriedAtS);
  INFO("first lost " << v.firstLostS.value_or(-1) << " s, relocalised " << v.relocalisedS.value_or(-1)
                     << " s, ATE after it " << v.ateAfterM() << " m over " << v.posedAfter << " frames, worst good "
                     << "after the set-down " << v.worstGoodAfterM << " m");
  REQUIRE(v.firstLostS);
  CHECK(*v.firstLostS > kTurnCarriedAtS);
  REQUIRE(v.relocalisedS);
  CHECK(*v.relocalisedS - kTurnCarriedAtS <= kSetDownWithinS);
  CHECK(v.ateAfterM() <= kAteAfterM);
  CHECK(v.goodOff == 0);
}
