// Symlinks and hard links planted in the daemon's output directory (issue 44 S3): every temporary name the
// daemon used before (predictable) and every output name is made beforehand as a link to a victim outside the
// directory (some dangling); after a pass with model.png, mesh.ply and report.html, with rotated segments,
// every victim is as it was and no dangling target came to exist. A map_slabs that is a symlink to a foreign
// directory is refused: the map's retention (keep_slabs_mib) counts the slab files it finds there as an
// earlier start's and, at 51764fd, deleted the foreign ones (S2).

#include <unistd.h>

#include "tests/daemon/daemon_e2e.h"
#include "tests/daemon/process.h"
#include "tests/support/files.h"
#include "tests/support/planted_links.h"

using namespace sb::test::e2e;
namespace fs = std::filesystem;

TEST_CASE("slamboosterd: no link planted in the output directory is written through", "[daemon][system]") {
  TempDir tmp;
  const std::string dir = sb::test::scratchDir("daemon_symlinks");
  const std::string out = dir + "/out", victims = dir + "/victims";
  fs::create_directories(out);
  fs::create_directories(victims);
  std::vector<std::string> names = {"summary.json.tmp", "model.png.tmp", "mesh.ply.partial", "mesh.ply.tmp",
                                    "mesh.ply.vertices.tmp", "mesh.ply.faces.tmp", "report.html.tmp",
                                    "summary.json", "model.png", "mesh.ply", "report.html", "energy.jsonl",
                                    "power.csv", "trajectory.tum", "frames.jsonl"};
  for (const char* stream : {"trajectory-%06d.tum", "frames-%06d.jsonl"})
    for (int n = 1; n <= 3; ++n) {
      char name[64];
      std::snprintf(name, sizeof name, stream, n);
      names.push_back(name);
    }
  const sb::test::PlantedLinks planted = sb::test::plantLinks(out, victims, names);
  auto args = daemonArgs(tmp.path + "/s.sock", out, "fast", "exit");
  for (const char* set : {"output.mesh=true", "output.model_png=true", "output.report=true",
                          "output.rotation.mode=always"})
    args.insert(args.end(), {"--set", set});
  sb::test::ChildProcess d(args, {}, dir + "/log.txt");
  const int status = d.wait(120);
  INFO(d.log());
  CHECK(status == 0);
  const std::vector<std::string> touched = sb::test::touchedVictims(planted);
  CAPTURE(touched);
  CHECK(touched.empty());
  CHECK(fs::is_regular_file(fs::symlink_status(out + "/summary.json")));
  CHECK(sb::test::readJson(out + "/summary.json")["complete"] == true);
}

TEST_CASE("slamboosterd: a map_slabs that is a symlink to a foreign directory is refused, its files stay",
          "[daemon][system]") {
  TempDir tmp;
  const std::string dir = sb::test::scratchDir("daemon_symlinks_slabs");
  const std::string out = dir + "/out", foreign = dir + "/foreign";
  // The corridor drive at 160x120 in a 5 m volume: slabs of about 0.3, 4 and 9 MB within 220 frames, more
  // than keep_slabs_mib's least (16 MiB) together, so the retention removes the oldest.
  const auto synth = sb::test::runCommand(kTool + " synth --out " + dir +
                                          "/drive --scene corridor "
                                          "--corridor-length 12 --stress drive --frames 220 --width 160 "
                                          "--height 120 --fx 120.3 --fy 120 --threads 2 --overwrite");
  INFO(synth.output);
  REQUIRE(synth.exitCode == 0);
  std::ofstream(dir + "/pipeline.json") << R"({"volume_size_m": 5})";
  fs::create_directories(out);
  fs::create_directories(foreign);
  std::ofstream(foreign + "/slab-000001.ply") << "foreign slab\n";
  std::ofstream(foreign + "/slab-000002.ply") << "foreign slab\n";
  fs::create_directory_symlink(foreign, out + "/map_slabs");
  sb::test::ChildProcess d({kDaemon,
                            "--input",
                            dir + "/drive",
                            "--out",
                            out,
                            "--socket",
                            tmp.path + "/s.sock",
                            "--pacing",
                            "fast",
                            "--at-end",
                            "exit",
                            "--controller",
                            "default",
                            "--set",
                            "slam.pipeline_config=" + dir + "/pipeline.json",
                            "--set",
                            "slam.threads=2",
                            "--set",
                            "output.mesh=true",
                            "--set",
                            "output.rotation.keep_slabs_mib=16"},
                           {}, dir + "/log.txt");
  const int status = d.wait(240);
  INFO(d.log());
  CHECK(status == 1);  // refused: an error exit, not a signal
  CHECK(d.log().find("map_slabs' is a symlink") != std::string::npos);
  CHECK(sb::test::readText(foreign + "/slab-000001.ply") == "foreign slab\n");
  CHECK(sb::test::readText(foreign + "/slab-000002.ply") == "foreign slab\n");
  size_t files = 0;
  for (const auto& entry : fs::directory_iterator(foreign)) files += !entry.path().empty();
  CHECK(files == 2);
}
