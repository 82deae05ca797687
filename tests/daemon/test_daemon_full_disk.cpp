// slamboosterd with the moving volume's map (output.mesh) on a 20 MiB disk (issue 44 M3, issue 53 finding 8):
// a tmpfs, so root only (a failure under CI, a warning elsewhere). The corridor drive at 160x120 in a 5 m
// volume of 256^3 makes slabs of 0.26, 4.2, 9.2, 10.2 and 10.3 MB; a slab's write takes its file's size and a
// chunk at its peak (mesh/mesh_pieces.h).
// - Without rotation (a replay: no retention, every slab kept) the slabs together pass 20 MiB: the pass ends
//   at the first write that meets the full disk with exit 1 and summary.json says why ("complete": false,
//   "error" with the full disk, "error_file" naming the output), and no temporary is left in map_slabs. Which
//   output meets it first is a race between the slab worker and the SLAM thread: a slab that does not fit,
//   or, when the slab took the disk's last bytes, the trajectory, frames.jsonl or summary.json of the next
//   frame (before issue 53 finding 8's fix summary.json then kept the last frame's snapshot, without
//   "complete": tests/runtime/test_run_full_disk.cpp makes each of those first, deterministically). The same
//   drive at 128^3 (slabs up to 2 MB, mesh.ply 12 MB) fits the same disk: exit 0, complete.
// - With rotation the older slabs give way (the newest stays) and every slab is written.
// The peak use of the disk is measured (statvfs every 10 ms) and printed.

#include <sys/mount.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <thread>
#include <vector>

#include "tests/daemon/daemon_e2e.h"
#include "tests/daemon/process.h"
#include "tests/support/files.h"

using namespace sb::test::e2e;
namespace fs = std::filesystem;

namespace {

constexpr uint64_t kDiskBytes = 20ull << 20;

struct Tmpfs {
  std::string dir;
  explicit Tmpfs(const std::string& d, uint64_t bytes = kDiskBytes) : dir(d) {
    fs::create_directories(dir);
    const std::string size = "size=" + std::to_string(bytes);
    if (::mount("tmpfs", dir.c_str(), "tmpfs", 0, size.c_str()) != 0)
      throw std::runtime_error("cannot mount a tmpfs on " + dir);
  }
  ~Tmpfs() { ::umount2(dir.c_str(), MNT_DETACH); }
};

uint64_t usedBytes(const std::string& dir) {
  struct statvfs s {};
  if (::statvfs(dir.c_str(), &s) != 0) return 0;
  return uint64_t(s.f_blocks - s.f_bfree) * s.f_frsize;
}

struct Pass {
  int code = -3;
  uint64_t peakBytes = 0;
  std::string log;
};

// The daemon on the drive into `disk`/out (fast, to the end), the disk's use polled meanwhile.
Pass runOn(const std::string& disk, const std::string& drive, const std::string& pipeline,
           const std::vector<std::string>& more = {}) {
  TempDir tmp;
  std::atomic<bool> done{false};
  Pass pass;
  std::thread poll([&] {
    while (!done) {
      pass.peakBytes = std::max(pass.peakBytes, usedBytes(disk));
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  });
  std::vector<std::string> args{kDaemon, "--input", drive, "--out", disk + "/out", "--socket",
                                tmp.path + "/s.sock", "--pacing", "fast", "--at-end", "exit"};
  args.insert(args.end(), {"--controller", "default", "--set", "slam.pipeline_config=" + pipeline, "--set",
                           "slam.threads=2", "--set", "output.mesh=true"});
  args.insert(args.end(), more.begin(), more.end());
  sb::test::ChildProcess d(args, {}, disk + "-log.txt");
  pass.code = d.wait(240);
  done = true;
  poll.join();
  pass.log = d.log();
  return pass;
}

// The corridor drive (220 frames at 160x120) and the two volumes' settings, made once.
const std::string& fullDiskDrive() {
  static const std::string dir = [] {
    const std::string d = sb::test::scratchDir("daemon_full_disk");
    const auto synth = sb::test::runCommand(kTool + " synth --out " + d +
                                            "/drive --scene corridor "
                                            "--corridor-length 12 --stress drive --frames 220 --width 160 "
                                            "--height 120 --fx 120.3 --fy 120 --threads 2 --overwrite");
    INFO(synth.output);
    REQUIRE(synth.exitCode == 0);
    std::ofstream(d + "/p256.json") << R"({"volume_size_m": 5, "volume_resolution": 256})";
    std::ofstream(d + "/p128.json") << R"({"volume_size_m": 5, "volume_resolution": 128})";
    return d;
  }();
  return dir;
}

bool rootOrWarn() {
  if (::geteuid() == 0) return true;
  if (std::getenv("CI")) FAIL("not root: this test needs a tmpfs (mount)");
  WARN("skipped: not root, no tmpfs for a 20 MiB disk");
  return false;
}

}  // namespace

TEST_CASE(
    "slamboosterd on a 20 MiB disk: a slab that cannot fit ends the pass with the error in summary.json",
    "[daemon][system][disk]") {
  if (!rootOrWarn()) return;
  const std::string& dir = fullDiskDrive();

  {
    const Tmpfs disk(dir + "/disk256");
    const Pass pass = runOn(disk.dir, dir + "/drive", dir + "/p256.json");
    INFO(pass.log);
    WARN("256^3: peak use of the 20 MiB disk " << pass.peakBytes << " bytes");
    CHECK(pass.code == 1);  // an error exit, not a signal or a hang
    const nlohmann::json summary = sb::test::readJson(disk.dir + "/out/summary.json");
    CHECK(summary.value("complete", true) == false);
    const std::string error = summary.value("error", "");
    CHECK(error.find("No space left on device") != std::string::npos);
    // Which output met the full disk first (issue 53): a slab or one of the next frame's files, named.
    const std::string file = summary.value("error_file", "");
    WARN("256^3: the first output to meet the full disk: " << file);
    const bool slab = file.rfind("map_slabs/slab-", 0) == 0;
    CHECK((slab || file == "trajectory.tum" || file == "frames.jsonl" || file == "summary.json"));
    CHECK(error.find(slab ? file.substr(std::string("map_slabs/").size()) : file) != std::string::npos);
    // The summary counts the frames frames.jsonl holds: the pass ended at that frame.
    CHECK(summary.value("frames", size_t(0)) == sb::test::dataLines(disk.dir + "/out/frames.jsonl"));
    for (const auto& entry : fs::directory_iterator(disk.dir + "/out/map_slabs")) {
      INFO(entry.path());
      CHECK(entry.path().extension() == ".ply");  // no temporary left
    }
    CHECK(pass.peakBytes <= kDiskBytes);
  }
  {
    const Tmpfs disk(dir + "/disk128");
    const Pass pass = runOn(disk.dir, dir + "/drive", dir + "/p128.json");
    INFO(pass.log);
    WARN("128^3: peak use of the 20 MiB disk " << pass.peakBytes << " bytes");
    CHECK(pass.code == 0);
    const nlohmann::json summary = sb::test::readJson(disk.dir + "/out/summary.json");
    CHECK(summary.value("complete", false) == true);
    CHECK_FALSE(summary.contains("error"));
    CHECK(fs::file_size(disk.dir + "/out/mesh.ply") > 0);
  }
}

TEST_CASE("slamboosterd on a 24 MiB disk with rotation: every slab is written, the oldest giving way",
          "[daemon][system][disk]") {
  // Issue 53 (finding 8): with rotation the slab files give way to a full disk, but a slab's write took twice
  // its file (the vertices and faces aside, then the file) and room was made for twice the largest slab: on
  // 20 MiB the third slab (9.2 MB, with the newest, 4.2 MB, kept) found 13 MiB free and the SLAM thread
  // stopped; on this 24 MiB disk the fourth (10.2 MB beside the third) does ("slab-000004.ply ... No space
  // left on device", 15 MB free for a 20 MB need). Now a write takes its file's size and a chunk, and room is
  // made for one slab: all five slabs are written, each beside the newest before it (the one kept while the
  // next is written), the older removed for space, and the pass goes through every frame. The disk must
  // still hold two slabs (the newest and the next): 24 MiB leaves 4 MB to spare; 20 MiB is the edge
  // (measured: passes with under 0.1 MB to spare). mesh.ply at the end (the newest slab and the final volume,
  // written beside that slab) does not fit on this disk: that is the one error left, and it names mesh.ply.
  if (!rootOrWarn()) return;
  const std::string& dir = fullDiskDrive();
  constexpr uint64_t kRotatedDiskBytes = 24ull << 20;
  const Tmpfs disk(dir + "/disk256rot", kRotatedDiskBytes);
  const Pass pass = runOn(disk.dir, dir + "/drive", dir + "/p256.json",
                          {"--set", "output.rotation.mode=always"});
  INFO(pass.log);
  WARN("256^3 with rotation: peak use of the 24 MiB disk " << pass.peakBytes << " bytes");
  CHECK(pass.log.find("stopped after 220 frames") != std::string::npos);
  const nlohmann::json summary = sb::test::readJson(disk.dir + "/out/summary.json");
  const std::string error = summary.value("error", "");
  CHECK(error.find("slab-") == std::string::npos);
  if (!error.empty()) CHECK(error.find("mesh.ply") != std::string::npos);
  REQUIRE(summary.contains("moving_volume"));
  CHECK(summary["moving_volume"].value("shifts", 0) == 5);
  CHECK(summary["moving_volume"].value("slab_files_removed", 0) == 4);
  std::vector<std::string> kept;
  for (const auto& entry : fs::directory_iterator(disk.dir + "/out/map_slabs"))
    kept.push_back(entry.path().filename().string());
  CHECK(kept == std::vector<std::string>{"slab-000005.ply"});  // the newest, whole; no temporary left
  CHECK(pass.peakBytes <= kRotatedDiskBytes);
}
