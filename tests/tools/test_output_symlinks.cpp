// Symlinks and hard links planted in an output directory (issue 44 S3, S2): whoever can create files in the
// output directory of `slambooster run` must not make it create, truncate, overwrite or delete a file
// anywhere else. Every temporary name the tool used before (predictable: summary.json.tmp, mesh.ply.partial,
// map_slabs/slab-000001.ply.partial, ...) and every output name is made beforehand as a symlink to a victim
// outside the directory (some dangling: the target must not be created), one output name as a hard link;
// after a run with the mesh and map slabs, every victim is as it was. A map_slabs that is a symlink to a
// foreign directory is refused and the foreign slab stays.

#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/support/files.h"
#include "tests/support/planted_links.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

namespace fs = std::filesystem;
using sb::test::runCommand;

namespace {

const std::string kTool = sb::test::testBinary("SB_TEST_SLAMBOOSTER", SB_SLAMBOOSTER_BIN);

// The first 150 frames of the corridor drive at 160x120 (shifts, so map slabs, within the first 100).
const std::string& drive() {
  static const std::string seq = [] {
    const std::string dir = sb::test::scratchDir("output_symlinks_drive") + "/drive";
    const auto r = runCommand(kTool + " synth --out " + dir +
                              " --scene corridor --corridor-length 12 --stress drive --frames 150"
                              " --width 160 --height 120 --fx 120.3 --fy 120 --threads 2 --overwrite");
    if (r.exitCode != 0) throw std::runtime_error("synth failed: " + r.output);
    return dir;
  }();
  return seq;
}

// The names `run` wrote or used as temporaries in an output directory before issue 44, and its outputs.
std::vector<std::string> plantedNames() {
  std::vector<std::string> names = {"summary.json.tmp", "model.png.tmp", "mesh.ply.partial", "mesh.ply.tmp",
                                    "mesh.ply.vertices.tmp", "mesh.ply.faces.tmp", "mesh.ply.partial.tmp",
                                    "report.html.tmp", "summary.json", "model.png", "mesh.ply", "report.html",
                                    "energy.jsonl", "trajectory.tum", "run.log"};
  for (int n = 1; n <= 6; ++n) {
    char slab[64];
    std::snprintf(slab, sizeof slab, "map_slabs/slab-%06d.ply", n);
    for (const char* suffix : {".partial", ".partial.tmp", ".partial.vertices.tmp", ".partial.faces.tmp", ".tmp",
                               ".vertices.tmp", ".faces.tmp"})
      names.push_back(std::string(slab) + suffix);
  }
  return names;
}

}  // namespace

TEST_CASE("run --mesh: no symlink or hard link planted in the output directory is written through",
          "[tools][hostile][system]") {
  const std::string dir = sb::test::scratchDir("output_symlinks_run");
  const std::string out = dir + "/out", victims = dir + "/victims";
  fs::create_directories(out + "/map_slabs");
  fs::create_directories(victims);
  sb::test::PlantedLinks planted = sb::test::plantLinks(out, victims, plantedNames());
  const std::string linked = victims + "/hard";
  std::ofstream(linked) << "hard-linked victim\n";
  planted.before[linked] = sb::test::readText(linked);
  REQUIRE(::link(linked.c_str(), (out + "/frames.jsonl").c_str()) == 0);

  const auto r = runCommand("timeout 300 " + kTool + " run " + drive() + " --controller default --volume-size 5 --threads 2 --mesh --quiet --out " + out);
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  const std::vector<std::string> touched = sb::test::touchedVictims(planted);
  CAPTURE(touched);
  CHECK(touched.empty());
  // The outputs are files of their own, and there were slabs to write.
  for (const char* name : {"summary.json", "trajectory.tum", "frames.jsonl", "mesh.ply"}) {
    INFO(name);
    CHECK(fs::is_regular_file(fs::symlink_status(out + "/" + name)));
  }
  size_t slabs = 0;
  for (const auto& entry : fs::directory_iterator(out + "/map_slabs"))
    slabs += fs::is_regular_file(fs::symlink_status(entry.path())) && entry.path().extension() == ".ply";
  CHECK(slabs > 0);
  CHECK(sb::test::readJson(out + "/summary.json")["complete"] == true);
}

TEST_CASE("run: a map_slabs that is a symlink to a foreign directory is refused, its files stay",
          "[tools][hostile][system]") {
  const std::string dir = sb::test::scratchDir("output_symlinks_slabs");
  const std::string out = dir + "/out", foreign = dir + "/foreign";
  fs::create_directories(out);
  fs::create_directories(foreign);
  std::ofstream(foreign + "/slab-000001.ply") << "foreign slab\n";
  std::ofstream(foreign + "/slab-000002.ply") << "foreign slab\n";
  fs::create_directory_symlink(foreign, out + "/map_slabs");
  const auto r = runCommand("timeout 300 " + kTool + " run " + drive() + " --controller default --volume-size 5 --threads 2" +
                            " --mesh --quiet --out " + out);
  INFO(r.output);
  CHECK(r.exitCode == 1);
  CHECK(r.output.find("map_slabs' is a symlink") != std::string::npos);
  CHECK(sb::test::readText(foreign + "/slab-000001.ply") == "foreign slab\n");
  CHECK(sb::test::readText(foreign + "/slab-000002.ply") == "foreign slab\n");
  size_t files = 0;
  for (const auto& entry : fs::directory_iterator(foreign)) files += !entry.path().empty();
  CHECK(files == 2);
}
