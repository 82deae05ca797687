// A run on a full disk (issue 53 finding 8): whichever output meets the full disk first (trajectory.tum,
// frames.jsonl or summary.json) ends the run at that frame, and summary.json says so: "complete": false, the
// "error" with the system's reason, "error_file" naming the output. Before, a run whose frames.jsonl met the
// full disk first (the daemon's map slab had taken the last bytes) left summary.json as the last frame's
// snapshot, without "complete" or "error": the summary's own rewrite found the disk full too.
//
// Deterministic, no timing: a tmpfs (root only; a failure under CI, a warning elsewhere) counts whole pages,
// so after each frame the room left in each file's last page decides which file's next line needs a new page
// first. The disk is filled to its last page after the first frame where the chosen file's next line cannot
// fit in its last page and the files written before it in a frame (trajectory, then frames.jsonl, then
// summary.json, always a new file) can; the next frame then fails on that file.

#include <fcntl.h>
#include <sys/mount.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "runtime/run.h"
#include "tests/pipeline/synthetic_room.h"
#include "tests/support/files.h"
#include "tests/support/test_data.h"

namespace fs = std::filesystem;

namespace {

class FixedController final : public sb::Controller {
 public:
  const std::string& name() const override { return name_; }
  sb::Knobs initialKnobs() const override { return sb::parseKnobs("csr=2"); }
  sb::Decision decide(const sb::Observation&) override { return sb::Decision{}; }

 private:
  std::string name_ = "fixed";
};

struct Tmpfs {
  std::string dir;
  Tmpfs(const std::string& d, uint64_t bytes) : dir(d) {
    ::umount2(dir.c_str(), MNT_DETACH);  // left over from a test run that was killed
    fs::create_directories(dir);
    const std::string size = "size=" + std::to_string(bytes);
    if (::mount("tmpfs", dir.c_str(), "tmpfs", 0, size.c_str()) != 0)
      throw std::runtime_error("cannot mount a tmpfs on " + dir);
  }
  ~Tmpfs() { ::umount2(dir.c_str(), MNT_DETACH); }
};

uint64_t pageBytes(const std::string& dir) {
  struct statvfs s {};
  REQUIRE(::statvfs(dir.c_str(), &s) == 0);
  return s.f_bsize;
}

uint64_t freeBytes(const std::string& dir) {
  struct statvfs s {};
  REQUIRE(::statvfs(dir.c_str(), &s) == 0);
  return uint64_t(s.f_bavail) * s.f_frsize;
}

// The bytes a file can still take without a new page.
uint64_t roomInLastPage(const std::string& path, uint64_t page) {
  const uint64_t size = fs::file_size(path);
  return (page - size % page) % page;
}

// The shortest and the longest line of a file (its data lines).
std::pair<size_t, size_t> lineLengths(const std::string& path) {
  std::ifstream in(path);
  size_t shortest = std::numeric_limits<size_t>::max(), longest = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    shortest = std::min(shortest, line.size() + 1);
    longest = std::max(longest, line.size() + 1);
  }
  return {shortest, longest};
}

// Takes every free page of the file system of `dir` (a file there, written until the disk is full).
void fillDisk(const std::string& dir) {
  const int fd = ::open((dir + "/filler").c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  REQUIRE(fd >= 0);
  const std::string block(4096, 'x');
  while (::write(fd, block.data(), block.size()) > 0) {
  }
  while (::write(fd, block.data(), 1) > 0) {
  }
  ::close(fd);
  REQUIRE(freeBytes(dir) == 0);
}

// A run of the synthetic room into `disk`/out; after the first frame where `first` is the file whose next
// line meets the full disk first, the disk is filled and the next frame must fail. Returns the summary.
nlohmann::json runUntilFull(const std::string& disk, const std::string& first) {
  const sb::test::Room room;
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  sb::PipelineConfig config;
  config.volumeSize = 3.0f;
  config.volumeResolution = 64;
  config.bootstrapFrames = 1;
  sb::ThreadPool pool(2);
  auto pipeline = sb::Pipeline::createCpu(config, k, pool);
  const Eigen::Isometry3d start = pipeline->initialPose();
  const auto frame = [&](size_t i) {
    Eigen::Isometry3d pose = start;
    pose.translation().x() += 0.002 * double(i % 100);
    return sb::test::renderRoom(room, pose, k, i);
  };
  const std::string out = disk + "/out";
  sb::RunOutputs outputs;
  outputs.dir = out;
  outputs.summary.sequence = "room";
  const uint64_t page = pageBytes(disk);
  const std::string trajectory = out + "/trajectory.tum", frames = out + "/frames.jsonl";
  constexpr uint64_t kMargin = 16;  // bytes: a line's length varies by a few digits
  {
    sb::Run run(std::move(pipeline), std::make_unique<FixedController>(), sb::test::kRoomDepthScale,
                sb::odometry::OdometryConfig{}, outputs);
    bool filled = false;
    for (size_t i = 0; i < 400 && !filled; ++i) {
      run.step(frame(i));
      if (i < 3) continue;  // a few lines of each file first, for their lengths
      const auto [trajShortest, trajLongest] = lineLengths(trajectory);
      const auto [framesShortest, framesLongest] = lineLengths(frames);
      const uint64_t trajRoom = roomInLastPage(trajectory, page), framesRoom = roomInLastPage(frames, page);
      const bool trajectoryFits = trajRoom >= trajLongest + kMargin;
      const bool trajectoryFails = trajRoom + kMargin <= trajShortest;
      const bool framesFits = framesRoom >= framesLongest + kMargin;
      const bool framesFails = framesRoom + kMargin <= framesShortest;
      const bool now = first == "trajectory.tum" ? trajectoryFails
                       : first == "frames.jsonl" ? trajectoryFits && framesFails
                                                 : trajectoryFits && framesFits;  // summary.json: a new file
      if (!now) continue;
      INFO("after frame " << i << ": " << trajRoom << " bytes left in trajectory.tum's last page, "
                          << framesRoom << " in frames.jsonl's");
      fillDisk(disk);
      CHECK_THROWS_AS(run.step(frame(i + 1)), sb::Error);
      filled = true;
    }
    REQUIRE(filled);
  }
  // The run is gone: nothing of its own left beside its outputs (no temporary, no room kept aside).
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(out)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  CHECK(names == std::vector<std::string>{"frames.jsonl", "summary.json", "trajectory.tum"});
  const nlohmann::json summary = sb::test::readJson(out + "/summary.json");
  // The frames the summary counts are those frames.jsonl holds (the frame that failed there is not).
  CHECK(summary.value("frames", size_t(0)) == sb::test::dataLines(frames));
  return summary;
}

}  // namespace

TEST_CASE("a run on a full disk: the first output that meets it ends the run and summary.json says which",
          "[runtime][disk]") {
  if (::geteuid() != 0) {
    if (std::getenv("CI")) FAIL("not root: this test needs a tmpfs (mount)");
    WARN("skipped: not root, no tmpfs for a small disk");
    return;
  }
  const std::string scratch = sb::test::scratchDir("run_full_disk");
  for (const std::string first : {"frames.jsonl", "trajectory.tum", "summary.json"}) {
    INFO("the first file to meet the full disk: " << first);
    const Tmpfs disk(scratch + "/disk-" + first, uint64_t(2) << 20);
    const nlohmann::json summary = runUntilFull(disk.dir, first);
    INFO(summary.dump(2));
    CHECK(summary.value("complete", true) == false);  // absent (the last frame's snapshot) before
    const std::string error = summary.value("error", "");
    CHECK(error.find("No space left on device") != std::string::npos);
    CHECK(error.find(first) != std::string::npos);
    CHECK(summary.value("error_file", "") == first);
  }
}
