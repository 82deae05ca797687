// The moving volume end to end (docs/moving-volume.md), as a user runs it: a corridor drive longer than the
// default 5 m volume (`slambooster synth --scene corridor --stress drive`, 160x120, the first 220 frames: the
// acceleration and 6 m of the drive at about 1.2 m/s, the camera 0.1 m from the volume's near face), run with
// DEFAULT in a 5 m volume. Fixed (`--fixed-volume`), the view leaves the cube and tracking is lost (measured:
// 44% tracked); moving (the default of `run`), the drive tracks (measured: 99.1%, ATE 3.5 cm, 4 shifts at the
// default volume_shift_threshold_m 1.5; 100%, 4.1 cm, 6 shifts at 1.0) and
// mesh.ply holds the slabs that left (map_slabs/) and the final volume, in the world frame.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/files.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

using sb::test::readJson;
using sb::test::runCommand;

namespace {

const std::string kTool = SB_SLAMBOOSTER_BIN;

// The vertex count in a PLY header.
size_t plyVertices(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  while (std::getline(in, line) && line != "end_header")
    if (line.rfind("element vertex ", 0) == 0) return std::stoul(line.substr(15));
  return 0;
}

}  // namespace

TEST_CASE("a corridor drive longer than the volume: lost in a fixed 5 m volume, tracked in a moving one",
          "[tools][moving_volume][system]") {
  const std::string dir = sb::test::scratchDir("moving_volume_drive");
  const auto synth = runCommand(kTool + " synth --out " + dir +
                                "/drive --scene corridor --corridor-length 12 --stress drive --frames 220"
                                " --width 160 --height 120 --fx 120.3 --fy 120 --threads 2 --overwrite");
  INFO(synth.output);
  REQUIRE(synth.exitCode == 0);
  const std::string run = kTool + " run " + dir + "/drive --controller default --volume-size 5 --threads 2 --quiet";
  const auto fixed = runCommand(run + " --fixed-volume --out " + dir + "/fixed");
  INFO(fixed.output);
  REQUIRE(fixed.exitCode == 0);
  std::filesystem::remove_all(dir + "/moving");
  const auto moving = runCommand(run + " --mesh --out " + dir + "/moving");
  INFO(moving.output);
  REQUIRE(moving.exitCode == 0);
  const nlohmann::json f = readJson(dir + "/fixed/summary.json");
  const nlohmann::json m = readJson(dir + "/moving/summary.json");
  INFO("fixed: " << f["tracked_percent"] << "% tracked, ATE " << f["ate"]["rmse_m"] << " m; moving: "
                 << m["tracked_percent"] << "% tracked, ATE " << m["ate"]["rmse_m"] << " m, " << m["moving_volume"]);
  CHECK(f.value("tracked_percent", 100.0) < 80.0);
  CHECK(!f.contains("moving_volume"));
  CHECK(m.value("tracked_percent", 0.0) >= 99.0);
  CHECK(m["ate"]["rmse_m"].get<double>() < 0.08);
  CHECK(m["moving_volume"]["shifts"].get<int>() >= 3);
  CHECK(m["config"]["volume_mode"] == "moving");
  // The whole run's map: the slabs written as they left, all in mesh.ply with the final volume.
  REQUIRE(m.contains("mesh_slabs"));
  const size_t slabs = m["mesh_slabs"].get<size_t>();
  CHECK(slabs >= 2);
  size_t slabVertices = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir + "/moving/map_slabs"))
    slabVertices += plyVertices(entry.path().string());
  CHECK(slabVertices > 1000);
  CHECK(plyVertices(dir + "/moving/mesh.ply") > slabVertices);
}
