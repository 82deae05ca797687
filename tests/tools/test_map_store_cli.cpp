// The map kept across runs end to end (issue 55), as a user runs it: two runs of one corridor drive
// (`slambooster synth --scene corridor --stress drive`, 160x120, 12 m corridor, 811 frames): run 1 drives frames
// 0-329 (the out leg, 9 m) with `--map-store STORE`; run 2 is the robot restarted at the place of frame 200
// (`--frames-from 200`, fresh odometry whose frame is the base there) driving on through the U-turn run 1 never
// saw and back along run 1's part, started with the same store. Run 2 must be localised in the store within 60
// frames (2 s; measured 2026-12-07: frame 25, the path behind the candidate fitting; 30 before that check), no
// frame before that `good`, and from then on its poses in run 1's frame: against the truth through run 1's own
// frame fitted on its whole poses (no refit; `slambooster eval --frame-of`, eval/trajectory_eval.h alignFrames),
// within the issue's 10 cm rmse and no frame more than 0.5 m off (measured: rmse 7.1 cm, max 13.1 cm from frame
// 25; 6.9 / 12.5 from frame 30 before; run 1's own ATE is 6.1 cm, run 2 follows run 1's map: it is 2% short
// along the corridor). Fitted on run 1's positions alone, a straight drive, the frame's rotation about the
// corridor was free and run 2, 0.8 m beside run 1 on the way back, measured 15.8 cm. frames.jsonl says
// `kept_map` localising before the localised frame and localised from it on (a new store's run: absent). A drive
// in another building (the corridor of seed 7) given a copy of run 1's store is never localised in it
// (measured: 568 of 568 frames lost; before the wheels' check it matched at frame 6 with a pair agreement of
// 0.92), and the store is left byte for byte as it was.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "core/trajectory.h"
#include "eval/trajectory_eval.h"
#include "tests/support/files.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"
#include "tests/tools/map_store_runs.h"

using sb::test::readJson;
using sb::test::runCommand;
using namespace sb::test::map_store;
namespace fs = std::filesystem;

namespace {

// Frames whose relocalisation had an acceptable attempt (a candidate found, held, or the one relocalised) and the
// most held in a row, from frames.jsonl.
struct Evidence {
  size_t frames = 0;
  int mostHeld = 0;
};
Evidence evidenceOf(const std::string& out) {
  Evidence e;
  std::ifstream frames(out + "/frames.jsonl");
  for (std::string line; std::getline(frames, line);) {
    const auto j = nlohmann::json::parse(line);
    if (!j.contains("relocalisation")) continue;
    const std::string why = j["relocalisation"].value("why", std::string());
    if (why.find("candidate found") != std::string::npos || why.find("held") != std::string::npos ||
        why.find("relocalised") != std::string::npos)
      ++e.frames;
    e.mostHeld = std::max(e.mostHeld, j["relocalisation"].value("confirmed", 0));
  }
  return e;
}

std::map<std::string, std::string> filesOf(const std::string& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files[e.path().string()] = sb::test::readText(e.path().string());
  return files;
}

// Run 2's poses from its localised frame on, in run 1's frame (run 1's alignment to the truth, no refit).
sb::AteResult ateInFirstFrame(const std::string& first, const std::string& out2, const std::string& run2,
                              double localisedS) {
  const sb::Trajectory est1 = sb::readTumTrajectory(first + "/out1/trajectory.tum");
  const sb::Trajectory gt1 = sb::readTumTrajectory(first + "/run1/groundtruth.txt");
  const Eigen::Isometry3d frame1 = sb::alignFrames(est1, gt1);
  sb::Trajectory est2 = sb::readTumTrajectory(out2 + "/trajectory.tum");
  est2.erase(std::remove_if(est2.begin(), est2.end(),
                            [&](const sb::TimedPose& p) { return p.timestamp < localisedS; }),
             est2.end());
  return sb::computeAte(est2, sb::readTumTrajectory(run2 + "/groundtruth.txt"), {}, &frame1);
}

// Whether frames.jsonl says a candidate was refused because the path behind it did not fit the kept surface.
bool pathRefused(const std::string& out) {
  return sb::test::readText(out + "/frames.jsonl").find("an earlier view does not fit the kept surface") !=
         std::string::npos;
}

// A run's map.pgm with map.yaml's origin and resolution and map_frame.json's transform (navmap/map_files.h).
struct GridMap {
  int width = 0, height = 0;
  double resolution = 0.0, originX = 0.0, originY = 0.0;
  std::vector<uint8_t> cells;  // row 0 the top (the highest y): 0 occupied, 254 free, 205 unknown
  nlohmann::json frame;
  bool known(long x, long y) const {  // cell (x, y) from the origin, y up
    if (x < 0 || y < 0 || x >= width || y >= height) return false;
    return cells[size_t(height - 1 - y) * size_t(width) + size_t(x)] != 205;
  }
};
GridMap gridOf(const std::string& out) {
  GridMap g;
  std::ifstream pgm(out + "/map.pgm", std::ios::binary);
  std::string magic, comment;
  std::getline(pgm, magic);
  std::getline(pgm, comment);
  int maxValue = 0;
  pgm >> g.width >> g.height >> maxValue;
  pgm.get();
  g.cells.resize(size_t(g.width) * size_t(g.height));
  pgm.read(reinterpret_cast<char*>(g.cells.data()), std::streamsize(g.cells.size()));
  REQUIRE((magic == "P5" && pgm && maxValue == 255));
  std::ifstream yaml(out + "/map.yaml");
  for (std::string line; std::getline(yaml, line);) {
    if (line.rfind("resolution: ", 0) == 0) g.resolution = std::stod(line.substr(12));
    if (line.rfind("origin: [", 0) == 0) std::sscanf(line.c_str(), "origin: [%lf, %lf", &g.originX, &g.originY);
  }
  g.frame = readJson(out + "/map_frame.json");
  return g;
}

// How much of `first`'s map (its known cells: free or occupied) `second`'s map knows too, by the cells' places
// in the map frame; and `second`'s cells `first` did not know.
struct Coverage {
  size_t firstKnown = 0, alsoInSecond = 0, secondOnly = 0;
  double share() const { return firstKnown ? double(alsoInSecond) / double(firstKnown) : 0.0; }
};
Coverage coverageOf(const GridMap& first, const GridMap& second) {
  Coverage c;
  const auto shift = [](double from, double to, double resolution) { return long(std::lround((from - to) / resolution)); };
  const long dx = shift(first.originX, second.originX, second.resolution),
             dy = shift(first.originY, second.originY, second.resolution);
  for (long y = 0; y < first.height; ++y)
    for (long x = 0; x < first.width; ++x)
      if (first.known(x, y)) {
        ++c.firstKnown;
        c.alsoInSecond += second.known(x + dx, y + dy);
      }
  for (long y = 0; y < second.height; ++y)
    for (long x = 0; x < second.width; ++x) c.secondOnly += second.known(x, y) && !first.known(x - dx, y - dy);
  return c;
}

// Run 2, continued in run 1's store, writes the map of both runs in one frame: map_frame.json run 1's, map.pgm
// knowing at least 95% of run 1's known cells (its own drive covers a part of them); and its wheels started from
// run 1's learnt calibration (summary.json's odometry, from odometry.bin).
void checkContinued(const std::string& out1, const std::string& out2, const std::string& store) {
  const GridMap g1 = gridOf(out1), g2 = gridOf(out2);
  CHECK(g2.frame["T_world_to_map"] == g1.frame["T_world_to_map"]);
  CHECK(g2.frame["source"].get<std::string>().find(store + "/navmap.bin") != std::string::npos);
  CHECK(g2.resolution == g1.resolution);
  const Coverage c = coverageOf(g1, g2);
  INFO("run 1's map: " << g1.width << "x" << g1.height << ", " << c.firstKnown << " cells known, " << c.alsoInSecond
                       << " of them in run 2's map (" << g2.width << "x" << g2.height << "), " << c.secondOnly
                       << " of run 2's not in run 1's");
  CHECK(c.firstKnown > 1000);
  CHECK(c.share() >= 0.95);
  const nlohmann::json o1 = readJson(out1 + "/summary.json")["odometry"],
                       o2 = readJson(out2 + "/summary.json")["odometry"];
  INFO("run 1's odometry: " << o1.dump() << "\nrun 2's: " << o2.dump());
  CHECK(o1.value("calibration_from", std::string()).empty());
  CHECK(o2.value("calibration_from", std::string()) == store + "/odometry.bin");
  REQUIRE(o2.contains("start_calibration_frames"));
  const size_t learnt = o1["calibration_frames"].get<size_t>();
  CHECK(learnt > 0);
  CHECK(o2["start_calibration_frames"].get<size_t>() >= learnt);  // run 1's last frame learnt after its summary
  CHECK(o2["start_calibration_frames"].get<size_t>() <= learnt + 1);
  // The same values but for that last frame's evidence (measured: 0.0220 and 0.0220, turns 0.0373 and 0.0359);
  // the prior would start at 0.
  CHECK(std::abs(o1["scale_error"].get<double>()) > 0.01);
  CHECK(o2["start_scale_error"].get<double>() == Approx(o1["scale_error"].get<double>()).margin(5e-3));
  CHECK(o2["start_yaw_scale_error"].get<double>() == Approx(o1["yaw_scale_error"].get<double>()).margin(5e-3));
}

}  // namespace

TEST_CASE("a restart in a kept map: localised within 60 frames, in the first run's frame; another building never",
          "[tools][map_store][system]") {
  const std::string dir = sb::test::scratchDir("map_store_cli");
  synth(" --frames-from 200 --out " + dir + "/run2");
  synth(" --frames-from 200 --seed 7 --out " + dir + "/other");
  const std::string first = firstRun().dir;
  const std::string store = dir + "/store", foreign = dir + "/store-copy";
  copyFirstStore(store);
  copyFirstStore(foreign);

  const nlohmann::json s1 = readJson(first + "/out1/summary.json");
  INFO("run 1: " << s1["map_store"].dump() << ", ATE " << s1["ate"]["rmse_m"]);
  CHECK(s1["map_store"]["kept"] == false);
  CHECK(s1["map_store"]["slab_files"].get<size_t>() >= 2);
  CHECK(s1["map_store"]["keyframes_saved"].get<size_t>() >= 5);
  CHECK(sb::test::readText(first + "/out1/frames.jsonl").find("kept_map") == std::string::npos);
  const auto before = filesOf(foreign);

  const nlohmann::json s2 = run(dir + "/run2", store, dir + "/out2");
  const nlohmann::json& m = s2["map_store"];
  INFO("run 2: " << m.dump() << ", tracking states " << s2["tracking_state"]["frames"].dump());
  CHECK(m["kept"] == true);
  REQUIRE(m["localised_frame"].is_number());
  const size_t localised = m["localised_frame"].get<size_t>();
  CHECK(localised <= 60);
  // No frame is good before the store's surface confirmed the view; each frame says where it stands.
  {
    std::ifstream frames(dir + "/out2/frames.jsonl");
    size_t goodBefore = 0, saidWrong = 0;
    for (std::string line; std::getline(frames, line);) {
      const auto j = nlohmann::json::parse(line);
      const bool localising = j.at("frame").get<size_t>() < localised;
      if (localising && j.at("state") != "lost") ++goodBefore;
      if (j.value("kept_map", std::string()) != (localising ? "localising" : "localised")) ++saidWrong;
    }
    CHECK(goodBefore == 0);
    CHECK(saidWrong == 0);
  }
  // From the localised frame on: run 2's poses in run 1's frame (run 1's alignment to the truth, no refit).
  const sb::AteResult ate = ateInFirstFrame(first, dir + "/out2", dir + "/run2", m["localised_s"].get<double>());
  INFO("run 2 in run 1's frame: rmse " << ate.rmse << " m, median " << ate.median << " m, max " << ate.max
                                       << " m over " << ate.matches << " frames");
  CHECK(ate.matches + localised + 5 >= s2["frames"].get<size_t>());
  CHECK(ate.rmse < 0.10);
  CHECK(ate.max < 0.5);
  // Mapping went on into the store, and the map and the wheels' calibration with it.
  CHECK(m["slab_files"].get<size_t>() > s1["map_store"]["slab_files"].get<size_t>());
  checkContinued(first + "/out1", dir + "/out2", store);

  const nlohmann::json s3 = run(dir + "/other", foreign, dir + "/out3");
  INFO("another building: " << s3["map_store"].dump() << ", states " << s3["tracking_state"]["frames"].dump());
  CHECK(s3["map_store"]["kept"] == true);
  CHECK(s3["map_store"]["localised_frame"].is_null());
  CHECK(s3["tracking_state"]["frames"].value("good", 0) == 0);
  CHECK(filesOf(foreign) == before);  // nothing written into a store the run was never localised in
}

// Another building's corridor end looks like the kept one's: two side walls meeting an end wall, the views on this
// drive that fix every motion and pair at the relocaliser's bar (2.1-2.9 m before the wall), and the wheels move a
// candidate there as they move the robot (docs/map-store.md). Before the path check the corridor of seed 7 from
// frame 150 had 17 frames with an acceptable attempt against the right restart's 16 and was refused only because
// they held 11 in a row, not 15; seed 3 from frame 200, 14 frames, 12 in a row; with confirming frames at
// tracking's conditioning seed 3 was localised at frame 63. What refuses them now is the path the wheels drove
// behind the candidate: its earlier views, put under the candidate, do not fit the kept surface (measured: the
// worst agreeing 0.50-0.61 within the noise, against 0.97-0.99 in the right building). This pins that both stay
// refused, and by that check (else the case tests nothing: a candidate that never reaches it is refused by luck).
TEST_CASE("other buildings pairing at the bar as long as the right place: refused by the path behind them",
          "[tools][map_store][system]") {
  const std::string dir = sb::test::scratchDir("map_store_cli_ends");
  synth(" --frames-from 150 --frames-to 260 --seed 7 --out " + dir + "/seed7");
  synth(" --frames-from 200 --frames-to 320 --seed 3 --out " + dir + "/seed3");
  const std::string store = dir + "/store";
  copyFirstStore(store);
  const auto before = filesOf(store);
  for (const char* other : {"seed7", "seed3"}) {
    const nlohmann::json s = run(dir + "/" + other, store, dir + "/out-" + other);
    const Evidence e = evidenceOf(dir + "/out-" + other);
    INFO(other << ": " << s["map_store"].dump() << ", " << e.frames << " frames with an acceptable attempt, "
               << e.mostHeld << " held in a row");
    CHECK(s["map_store"]["localised_frame"].is_null());
    CHECK(s["tracking_state"]["frames"].value("good", 0) == 0);
    CHECK(e.frames >= 5);
    CHECK(pathRefused(dir + "/out-" + other));
  }
  CHECK(filesOf(store) == before);
}

// The same restart and another building with the fault watch off, run 1 and run 2 alike (the default, on, is the
// case above: before the path check its restart's candidate, found at frame 18, held 14 of the 15 frames before the
// end wall took the view's conditioning under the relocaliser's bar and was never localised; off, it was).
TEST_CASE("with the fault watch off: a restart localised within 60 frames in the first run's frame, another building "
          "refused", "[tools][map_store][system]") {
  const std::string dir = sb::test::scratchDir("map_store_cli_unwatched");
  synth(" --frames-from 200 --frames-to 320 --out " + dir + "/run2");
  synth(" --frames-from 200 --frames-to 320 --seed 3 --out " + dir + "/seed3");
  const FirstRun& first = firstRun(kUnwatchedConfig);
  copyFirstStore(dir + "/store", kUnwatchedConfig);
  copyFirstStore(dir + "/store-copy", kUnwatchedConfig);
  const auto before = filesOf(dir + "/store-copy");

  const nlohmann::json s2 = run(dir + "/run2", dir + "/store", dir + "/out2", first.extra);
  const nlohmann::json& m = s2["map_store"];
  INFO("run 2: " << m.dump() << ", tracking states " << s2["tracking_state"]["frames"].dump());
  REQUIRE(m["localised_frame"].is_number());
  CHECK(m["localised_frame"].get<size_t>() <= 60);
  const sb::AteResult ate = ateInFirstFrame(first.dir, dir + "/out2", dir + "/run2", m["localised_s"].get<double>());
  INFO("run 2 in run 1's frame: rmse " << ate.rmse << " m, max " << ate.max << " m over " << ate.matches);
  CHECK(ate.rmse < 0.10);
  CHECK(ate.max < 0.5);
  // Run 2 drives 4 m of run 1's 9 m (frames 200-319 of 0-329): its map.pgm covers the rest from the store.
  checkContinued(first.dir + "/out1", dir + "/out2", dir + "/store");

  const nlohmann::json s3 = run(dir + "/seed3", dir + "/store-copy", dir + "/out3", first.extra);
  INFO("another building: " << s3["map_store"].dump());
  CHECK(s3["map_store"]["localised_frame"].is_null());
  CHECK(s3["tracking_state"]["frames"].value("good", 0) == 0);
  CHECK(pathRefused(dir + "/out3"));
  CHECK(filesOf(dir + "/store-copy") == before);

  // On the OpenCL backend (PoCL here) the same: it counts the pairs within the sensor's noise as the CPU backend
  // does (its maps read back, the same count), so the path behind a candidate is checked there too. Measured
  // (2026-12-07): the restart localised at frame 25 with the path fitting (5 of 5 earlier views over 1.0 m, worst
  // 0.987), as on the CPU; before the OpenCL backend counted them there was no path check on it and it was
  // localised at frame 30. Another building (seed 3) is refused by the path there as well.
  std::ofstream(dir + "/opencl.json") << R"({"backend": "opencl", "odometry": {"dispute_s": 0}})";
  const std::string opencl = " --config " + dir + "/opencl.json";
  copyFirstStore(dir + "/store-opencl", kUnwatchedConfig);
  copyFirstStore(dir + "/store-opencl-copy", kUnwatchedConfig);
  const nlohmann::json s4 = run(dir + "/run2", dir + "/store-opencl", dir + "/out4", opencl);
  INFO("run 2 on the OpenCL backend: " << s4["map_store"].dump());
  REQUIRE(s4["map_store"]["localised_frame"].is_number());
  CHECK(s4["map_store"]["localised_frame"].get<size_t>() <= 60);
  CHECK(sb::test::readText(dir + "/out4/frames.jsonl").find("the path behind it fits") != std::string::npos);
  const sb::AteResult ate4 =
      ateInFirstFrame(first.dir, dir + "/out4", dir + "/run2", s4["map_store"]["localised_s"].get<double>());
  INFO("run 2 on the OpenCL backend in run 1's frame: rmse " << ate4.rmse << " m, max " << ate4.max << " m");
  CHECK(ate4.rmse < 0.10);
  CHECK(ate4.max < 0.5);
  const nlohmann::json s5 = run(dir + "/seed3", dir + "/store-opencl-copy", dir + "/out5", opencl);
  INFO("another building on the OpenCL backend: " << s5["map_store"].dump());
  CHECK(s5["map_store"]["localised_frame"].is_null());
  CHECK(s5["tracking_state"]["frames"].value("good", 0) == 0);
  CHECK(pathRefused(dir + "/out5"));
}

TEST_CASE("a store of another voxel size is refused naming its format.json, and left as it was",
          "[tools][map_store][system]") {
  const std::string dir = sb::test::scratchDir("map_store_cli_refused");
  synth(" --frames-to 20 --out " + dir + "/seq");
  const std::string store = dir + "/store";
  fs::remove_all(store);
  run(dir + "/seq", store, dir + "/out1");
  const auto before = filesOf(store);
  fs::remove_all(dir + "/out2");
  const auto r = runCommand(kTool + " run " + dir + "/seq --volume-size 5 --volume-resolution 128 --quiet" +
                            " --map-store " + store + " --out " + dir + "/out2");
  INFO(r.output);
  CHECK(r.exitCode != 0);
  CHECK(r.output.find(store + "/format.json") != std::string::npos);
  CHECK(filesOf(store) == before);
}
