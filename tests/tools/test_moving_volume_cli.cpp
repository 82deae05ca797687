// The moving volume end to end (docs/moving-volume.md), as a user runs it: a corridor drive longer than the
// default 5 m volume (`slambooster synth --scene corridor --stress drive`, 160x120, the first 220 frames: the
// acceleration and 6 m of the drive at about 1.2 m/s, the camera 0.1 m from the volume's near face), run with
// DEFAULT in a 5 m volume, with the drive's odometry. Fixed (`--fixed-volume`), the view leaves the cube and
// tracking is lost (measured: 45.8% tracked); moving (the default of `run`), the drive keeps a pose on every frame
// (measured 2026-12-05: 93.5% tracked by ICP, 6.5% on the odometry, ATE 4.43 cm, 5 shifts) and
// mesh.ply holds the slabs that left (map_slabs/) and the final volume, in the world frame.
//
// The daemon on the same drive with output.mesh (its slabs on the map's worker thread, runtime/map_slabs.h):
// SIGTERM once a slab is on disk ends the pass cleanly: exit 0, every slab queued written (no .partial left),
// mesh.ply holding them all, summary.json complete.
#include <signal.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "tests/daemon/process.h"
#include "tests/support/files.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

using sb::test::readJson;
using sb::test::runCommand;

namespace {

const std::string kTool = SB_SLAMBOOSTER_BIN;

// The first 220 frames of the corridor drive at 160x120 in `dir`/drive.
void renderDrive(const std::string& dir) {
  const auto synth = runCommand(kTool + " synth --out " + dir +
                                "/drive --scene corridor --corridor-length 12 --stress drive --frames 220"
                                " --width 160 --height 120 --fx 120.3 --fy 120 --threads 2 --overwrite");
  INFO(synth.output);
  REQUIRE(synth.exitCode == 0);
}

size_t countFiles(const std::string& dir, const std::string& extension) {
  size_t n = 0;
  if (std::filesystem::is_directory(dir))
    for (const auto& entry : std::filesystem::directory_iterator(dir)) n += entry.path().extension() == extension;
  return n;
}

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
  renderDrive(dir);
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
  // The drive has its odometry (synth writes it): a frame whose view slides off the wheels follows them (state
  // odometry: posed, not tracked). Every frame keeps a pose, and ICP tracks the great majority (measured: 202 of
  // 216, the 14 others on the odometry where the view ran 3-5 cm ahead of the wheels and the truth; since the
  // fusion's prior carries the previous pose's covariance (2026-12-06), 192, ATE 4.52 cm against 4.40: the view
  // runs 5-8 cm off the wheels on the last 20 frames, before the corridor's end wall, at 160x120).
  const nlohmann::json& states = m["tracking_state"]["frames"];
  int frames = 0;
  for (const auto& count : states) frames += count.get<int>();
  CHECK(states["lost"].get<int>() <= frames / 100);
  CHECK(m.value("tracked_percent", 0.0) >= 85.0);
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

TEST_CASE("the daemon on the drive with output.mesh: SIGTERM after a slab writes every slab and the map",
          "[tools][moving_volume][daemon][system]") {
  const std::string dir = sb::test::scratchDir("moving_volume_daemon");
  renderDrive(dir);
  std::ofstream(dir + "/pipeline.json") << R"({"volume_size_m": 5})";
  char socketDir[] = "/tmp/sbd-mv-XXXXXX";  // socket paths must stay short
  REQUIRE(mkdtemp(socketDir) != nullptr);
  const std::string out = dir + "/out", slabs = out + "/map_slabs";
  sb::test::ChildProcess d({SB_SLAMBOOSTERD_BIN, "--input", dir + "/drive", "--out", out, "--socket",
                            std::string(socketDir) + "/s.sock", "--pacing", "recorded", "--at-end", "stop",
                            "--controller", "default", "--set", "slam.pipeline_config=" + dir + "/pipeline.json",
                            "--set", "slam.threads=2", "--set", "output.mesh=true", "--set",
                            "output.rotation.keep_slabs_mib=64"},
                           {}, dir + "/log.txt");
  // 220 frames at 30 fps: about 7 s; the first shift comes within the first 3 s.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (countFiles(slabs, ".ply") == 0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  INFO(d.log());
  REQUIRE(countFiles(slabs, ".ply") > 0);
  // STATUS counts the slab files on disk (docs/protocol.md): in `bytes`, and alone.
  const sb::test::CommandResult status = sb::test::runCommand(
      std::string(SB_SLAMBOOSTERCTL_BIN) + " --json --socket " + socketDir + "/s.sock status");
  INFO(status.output);
  REQUIRE(status.exitCode == 0);
  const nlohmann::json disk =
      nlohmann::json::parse(status.output.substr(0, status.output.find('\n')))["disk"];
  CHECK(disk["slab_files"].get<size_t>() >= 1);
  CHECK(disk["slab_bytes"].get<uint64_t>() > 0);
  CHECK(disk["bytes"].get<uint64_t>() > disk["slab_bytes"].get<uint64_t>());
  d.signal(SIGTERM);
  REQUIRE(d.wait(60) == 0);
  std::filesystem::remove_all(socketDir);
  const nlohmann::json m = readJson(out + "/summary.json");
  INFO(m.dump());
  CHECK(m["complete"] == true);
  CHECK(countFiles(slabs, ".partial") == 0);
  const size_t files = countFiles(slabs, ".ply");
  CHECK(m["mesh_slabs"].get<size_t>() == files);
  CHECK(m["moving_volume"]["shifts"].get<size_t>() >= files);
  CHECK(m["moving_volume"]["slab_files_removed"] == 0);
  size_t slabVertices = 0;
  for (const auto& entry : std::filesystem::directory_iterator(slabs)) slabVertices += plyVertices(entry.path().string());
  CHECK(plyVertices(out + "/mesh.ply") > slabVertices);
}
