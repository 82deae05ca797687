// What a run keeps of the base in a map store, and writes of the store, end to end (issue 55): the runs of
// tests/tools/map_store_runs.h (the corridor drive's first run, frames 0-329, with a new store; restarts given a
// copy of it).
//
// The mount's correction kept (odometry.bin) is restored only for the mount it was learnt against: the store
// records the mount the odometry assumed (its up axis in the camera frame, runtime/kept_odometry.h). A restart
// whose odometry assumes the same mount starts from the kept correction (summary.json odometry.start_mount_error_deg;
// on this drive run 1 learnt none, 0.0 deg: what is tested is the decision, the restore itself is
// tests/runtime/test_map_store_state.cpp's); one whose odometry assumes a mount pitched 3 degrees further (`synth
// --odom-mount-error 0,3,0`: a mount re-measured) starts fresh, said in the log and in
// odometry.start_mount_refused, with the change measured (start_mount_change_deg).
//
// mesh.ply of a run writing a store covers everything the store holds, in the store's frame: a restart from
// frame 200 (frames 200-319: the far end of the first run's 9 m and the U-turn) writes the surface of the first
// run's whole drive too, back to its start 6 m behind.
//
// One map from both runs: a restart driving on to the drive's end writes a map.pgm of both runs that scores as
// the first run's own against the corridor's true occupancy (slambooster eval-map).
#include <algorithm>
#include <catch2/catch.hpp>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "core/trajectory.h"
#include "tests/tools/map_store_runs.h"

using namespace sb::test::map_store;

TEST_CASE("a kept mount correction is restored for the mount it was learnt against, and not for another",
          "[tools][map_store][system]") {
  const std::string dir = sb::test::scratchDir("map_store_cli_mount");
  synth(" --frames-from 200 --frames-to 260 --out " + dir + "/same");
  synth(" --frames-from 200 --frames-to 260 --odom-mount-error 0,3,0 --out " + dir + "/moved");
  copyFirstStore(dir + "/store-same");
  copyFirstStore(dir + "/store-moved");

  std::string log;
  const nlohmann::json same = run(dir + "/same", dir + "/store-same", dir + "/out-same", "", &log)["odometry"];
  INFO("the same mount: " << same.dump());
  REQUIRE(same.contains("start_mount_change_deg"));
  CHECK(same["start_mount_change_deg"].get<double>() < 0.1);
  CHECK(same.contains("start_mount_error_deg"));
  CHECK_FALSE(same.contains("start_mount_refused"));
  CHECK(log.find("is not restored") == std::string::npos);

  const nlohmann::json moved = run(dir + "/moved", dir + "/store-moved", dir + "/out-moved", "", &log)["odometry"];
  INFO("a mount 3 degrees off: " << moved.dump() << "\n" << log);
  REQUIRE(moved.contains("start_mount_change_deg"));
  CHECK(moved["start_mount_change_deg"].get<double>() == Approx(3.0).margin(0.2));
  CHECK_FALSE(moved.contains("start_mount_error_deg"));
  REQUIRE(moved.contains("start_mount_refused"));
  CHECK(moved["start_mount_refused"].get<std::string>().find("the odometry's mount differs by 3.") != std::string::npos);
  CHECK(log.find("map store: the mount's correction kept in '" + dir + "/store-moved/odometry.bin'") !=
        std::string::npos);
  CHECK(log.find("start_mount_refused") != std::string::npos);
  // The wheels' calibration is the base's whatever the mount: both restarts start from it.
  CHECK(moved.value("calibration_from", std::string()) == dir + "/store-moved/odometry.bin");
}

namespace {

// The vertices of a binary little-endian PLY as mesh/ply_writer.h writes it (x y z, then nx ny nz or not).
std::vector<Eigen::Vector3f> plyVertices(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  size_t vertices = 0, properties = 0;
  bool inVertex = false;
  for (std::string line; std::getline(in, line) && line != "end_header";) {
    if (line.rfind("element vertex ", 0) == 0) {
      vertices = std::stoul(line.substr(15));
      inVertex = true;
    } else if (line.rfind("element", 0) == 0) {
      inVertex = false;
    } else if (inVertex && line.rfind("property float", 0) == 0) {
      ++properties;
    }
  }
  REQUIRE(properties >= 3);
  std::vector<float> values(vertices * properties);
  in.read(reinterpret_cast<char*>(values.data()), std::streamsize(values.size() * sizeof(float)));
  REQUIRE(in);
  std::vector<Eigen::Vector3f> out(vertices);
  for (size_t i = 0; i < vertices; ++i)
    out[i] = Eigen::Vector3f(values[i * properties], values[i * properties + 1], values[i * properties + 2]);
  return out;
}

}  // namespace

TEST_CASE("mesh.ply of a restart in a kept map covers everything the store holds, in its frame",
          "[tools][map_store][system]") {
  const std::string dir = sb::test::scratchDir("map_store_cli_mesh");
  synth(" --frames-from 200 --frames-to 320 --out " + dir + "/run2");
  copyFirstStore(dir + "/store");
  const nlohmann::json s2 = run(dir + "/run2", dir + "/store", dir + "/out2", " --mesh");
  const nlohmann::json& m = s2["map_store"];
  INFO("run 2: " << m.dump() << ", mesh_triangles " << s2.value("mesh_triangles", 0));
  REQUIRE(m["localised_frame"].is_number());  // writing the store: its mesh is the store's
  CHECK(m["mesh_slabs"] == m["slab_files"]);
  CHECK(s2["mesh_slabs"] == m["slab_files"]);
  const std::vector<Eigen::Vector3f> vertices = plyVertices(dir + "/out2/mesh.ply");
  REQUIRE(vertices.size() > 1000);
  // Every tenth of run 1's camera positions (the store's frame) has the corridor's surface within 1.5 m: its walls
  // (the corridor is 2 m wide), floor and ceiling. Run 2's own drive starts 6 m along from run 1's start.
  const sb::Trajectory run1 = sb::readTumTrajectory(firstRun().dir + "/out1/trajectory.tum");
  const sb::Trajectory own = sb::readTumTrajectory(dir + "/out2/trajectory.tum");
  REQUIRE(run1.size() > 100);
  REQUIRE(!own.empty());
  size_t positions = 0, covered = 0;
  double farthest = 0.0;  // of those positions from run 2's path, metres
  for (size_t i = 0; i < run1.size(); i += 10) {
    const Eigen::Vector3f p = run1[i].position().cast<float>();
    double nearestOwn = 1e9;
    for (const sb::TimedPose& o : own) nearestOwn = std::min(nearestOwn, double((o.position().cast<float>() - p).norm()));
    farthest = std::max(farthest, nearestOwn);
    ++positions;
    for (const Eigen::Vector3f& v : vertices)
      if ((v - p).norm() < 1.5f) {
        ++covered;
        break;
      }
  }
  INFO(covered << " of " << positions << " of run 1's positions have the surface within 1.5 m; the farthest is "
               << farthest << " m from run 2's path");
  CHECK(farthest > 4.0);  // run 1's start lies beyond what run 2's volume (5 m) saw from its own path
  CHECK(covered == positions);
}

namespace {

// `slambooster eval-map`'s precision and recall (its lines "precision P (...)" and "recall R (...)").
std::pair<double, double> gridScore(const std::string& args) {
  const auto r = sb::test::runCommand(kTool + " eval-map " + args);
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  const size_t p = r.output.find("precision "), q = r.output.find("recall ");
  REQUIRE((p != std::string::npos && q != std::string::npos));
  return {std::stod(r.output.substr(p + 10)), std::stod(r.output.substr(q + 7))};
}

}  // namespace

// One map from both runs: the restart from frame 200 drives on to the end of the drive (the way back over the
// first run's part, to the corridor's start, which the first run never saw behind it); its map.pgm, everything the
// store holds in the first run's frame, scored against the corridor's true occupancy aligned by the first run's
// frame (eval-map --frame-of: no refit on run 2). Measured (2026-12-08, scripts/map_store_grid.sh): run 1 alone
// precision 0.985, recall 1.000; both runs 0.977 and 0.992. Run 1's own score is the regression test
// of eval-map's alignment: fitted on positions alone (before 2026-12-08) the first run's straight 9 m let the frame
// roll about the corridor and the same grid scored 0.554 and 0.504.
TEST_CASE("the grid of a restart in a kept map: both runs' map against the corridor's true occupancy",
          "[tools][map_store][system]") {
  const std::string dir = sb::test::scratchDir("map_store_cli_grid");
  const FirstRun& first = firstRun();
  const std::pair<double, double> one = gridScore(first.dir + "/out1 " + first.dir + "/run1 --corridor-length 12");
  INFO("run 1 alone: precision " << one.first << ", recall " << one.second);
  CHECK(one.first >= 0.95);
  CHECK(one.second >= 0.9);

  synth(" --frames-from 200 --out " + dir + "/run2");
  copyFirstStore(dir + "/store");
  const nlohmann::json s2 = run(dir + "/run2", dir + "/store", dir + "/out2");
  INFO("run 2: " << s2["map_store"].dump());
  REQUIRE(s2["map_store"]["localised_frame"].is_number());
  const std::pair<double, double> both =
      gridScore(dir + "/out2 " + dir + "/run2 --corridor-length 12 --frame-of " + first.dir + "/out1/trajectory.tum " +
                first.dir + "/run1/groundtruth.txt");
  INFO("both runs: precision " << both.first << ", recall " << both.second);
  CHECK(both.first >= 0.95);
  CHECK(both.second >= 0.9);
  // Run 2's map reaches past run 1's start: the corridor's first metres, behind run 1's camera.
  const nlohmann::json f1 = sb::test::readJson(first.dir + "/out1/map_frame.json"),
                       f2 = sb::test::readJson(dir + "/out2/map_frame.json");
  CHECK(f2["free_cells"].get<size_t>() > f1["free_cells"].get<size_t>() + 1000);
}
