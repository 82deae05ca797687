// Symlinks and hard links planted in the daemon's output directory (issue 44 S3): every temporary name the
// daemon used before (predictable) and every output name is made beforehand as a link to a victim outside the
// directory (some dangling); after a pass with model.png, mesh.ply and report.html, with rotated segments,
// every victim is as it was and no dangling target came to exist.

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
