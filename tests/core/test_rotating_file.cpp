// Rotating output files and their retention (core/rotating_file.h, core/segment_store.h): segment names and
// headers, numbering across restarts, the byte, count and free-space limits (oldest first, across streams),
// and the single-file mode replays keep.
#include <sys/resource.h>

#include <catch2/catch.hpp>
#include <csignal>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/disk_full.h"
#include "core/error.h"
#include "core/rotating_file.h"
#include "core/segment_store.h"
#include "tests/support/files.h"
#include "tests/support/test_data.h"

using namespace sb;
namespace fs = std::filesystem;

namespace {

constexpr uint64_t kSegment = 64 * 1024;  // the smallest segment size allowed

RetentionLimits smallLimits() {
  RetentionLimits l;
  l.segmentBytes = kSegment;
  l.segmentSeconds = 0;
  l.keepBytes = 8 * kSegment;
  l.minFreeBytes = 0;
  return l;
}

std::string line(size_t bytes) {
  return std::string(bytes - 1, 'x') + "\n";
}

uint64_t bytesOf(const std::vector<std::string>& files) {
  uint64_t total = 0;
  for (const auto& f : files) total += fs::file_size(f);
  return total;
}

}  // namespace

TEST_CASE("without a store a rotating file is one file, truncated, with its header", "[core][rotation]") {
  const std::string dir = test::scratchDir("rotation_single");
  {
    RotatingFile f(dir, "trajectory.tum", "trajectory", "# header\n");
    f.append("1\n");
  }
  RotatingFile f(dir, "trajectory.tum", "trajectory", "# header\n");
  f.append("2\n");
  CHECK(f.path() == dir + "/trajectory.tum");
  CHECK(f.segment() == 0);
  CHECK(test::readText(dir + "/trajectory.tum") == "# header\n2\n");
  CHECK(streamFiles(dir, "trajectory.tum") == std::vector<std::string>{dir + "/trajectory.tum"});
  CHECK(f.files() == std::vector<std::string>{dir + "/trajectory.tum"});
}

TEST_CASE("segments are numbered, start with the header, and a restart numbers on", "[core][rotation]") {
  const std::string dir = test::scratchDir("rotation_segments");
  auto store = std::make_shared<SegmentStore>(dir, smallLimits());
  {
    RotatingFile f(dir, "frames.jsonl", "per-frame log", "# h\n", store);
    CHECK(f.path() == dir + "/frames-000001.jsonl");
    for (int i = 0; i < 40; ++i) f.append(line(4096));  // 160 KiB: segments of 64 KiB -> 3
    CHECK(f.segment() == 3);
    CHECK(f.files().size() == 3);
  }
  for (int n = 1; n <= 3; ++n) {
    const std::string text = test::readText(dir + "/" + segmentName("frames.jsonl", n));
    CHECK(text.rfind("# h\n", 0) == 0);
    CHECK(text.back() == '\n');
  }
  // A second writer (a restarted daemon) keeps the old segments and numbers on after them.
  auto again = std::make_shared<SegmentStore>(dir, smallLimits());
  RotatingFile f(dir, "frames.jsonl", "per-frame log", "# h\n", again);
  CHECK(f.path() == dir + "/frames-000004.jsonl");
  CHECK(f.files() == std::vector<std::string>{dir + "/frames-000004.jsonl"});
  CHECK(streamFiles(dir, "frames.jsonl").size() == 4);
  CHECK(streamFiles(dir, "frames.jsonl").front() == dir + "/frames-000001.jsonl");
  CHECK(again->usage().segments == 4);
  CHECK(again->usage().bytes == bytesOf(streamFiles(dir, "frames.jsonl")));
}

TEST_CASE("retention keeps every stream within the byte limit, oldest segments first", "[core][rotation]") {
  const std::string dir = test::scratchDir("rotation_bytes");
  const RetentionLimits limits = smallLimits();
  auto store = std::make_shared<SegmentStore>(dir, limits);
  RotatingFile frames(dir, "frames.jsonl", "per-frame log", "", store);
  RotatingFile trajectory(dir, "trajectory.tum", "trajectory", "# t\n", store);
  for (int i = 0; i < 2000; ++i) {  // 2 MB of frames, 200 KB of trajectory: far past the 512 KiB limit
    frames.append(line(1000));
    trajectory.append(line(100));
    const uint64_t onDisk =
        bytesOf(streamFiles(dir, "frames.jsonl")) + bytesOf(streamFiles(dir, "trajectory.tum"));
    REQUIRE(onDisk <= limits.keepBytes);
  }
  const SegmentUsage u = store->usage();
  CHECK(u.bytes == bytesOf(streamFiles(dir, "frames.jsonl")) + bytesOf(streamFiles(dir, "trajectory.tum")));
  CHECK(u.removedSegments > 0);
  // What is left is the newest: the frame log's last segments, and its first ones are gone.
  CHECK_FALSE(fs::exists(dir + "/frames-000001.jsonl"));
  CHECK(fs::exists(frames.path()));
  CHECK(streamFiles(dir, "frames.jsonl").back() == frames.path());
}

// The soak test once read the rotated outputs 755 bytes over output.rotation.keep_mib: a line was written
// first and the oldest segment removed after it. Here the write fails (the file-size limit, EFBIG), so what
// is on disk is what the rotating file left before writing: the room must already be made.
TEST_CASE("retention makes room before a line is written, not after", "[core][rotation]") {
  const std::string dir = test::scratchDir("rotation_room_first");
  const RetentionLimits limits = smallLimits();
  auto store = std::make_shared<SegmentStore>(dir, limits);
  RotatingFile frames(dir, "frames.jsonl", "per-frame log", "", store);
  // Up to the byte limit, and on until a line that passes it still fits in the current segment (no rotation).
  const auto gap = [&] { return limits.keepBytes - store->usage().bytes; };
  for (int i = 0; i < 2000 && (store->usage().removedSegments == 0 ||
                               fs::file_size(frames.path()) + gap() + 1 >= kSegment);
       ++i)
    frames.append(line(1000));
  const uint64_t onDisk = bytesOf(streamFiles(dir, "frames.jsonl"));
  REQUIRE(onDisk == store->usage().bytes);
  const size_t need = static_cast<size_t>(limits.keepBytes - onDisk) + 1;  // one byte past the limit
  REQUIRE(fs::file_size(frames.path()) + need < kSegment);

  rlimit old{};
  REQUIRE(::getrlimit(RLIMIT_FSIZE, &old) == 0);
  rlimit capped = old;
  capped.rlim_cur = static_cast<rlim_t>(fs::file_size(frames.path()));  // any byte more fails
  const auto previous = std::signal(SIGXFSZ, SIG_IGN);
  REQUIRE(::setrlimit(RLIMIT_FSIZE, &capped) == 0);
  bool threw = false;
  try {
    frames.append(line(need));
  } catch (const Error&) {
    threw = true;
  }
  ::setrlimit(RLIMIT_FSIZE, &old);
  std::signal(SIGXFSZ, previous);
  CHECK(threw);
  CHECK(bytesOf(streamFiles(dir, "frames.jsonl")) + need <= limits.keepBytes);
}

TEST_CASE("retention by segment count and by free space", "[core][rotation]") {
  const std::string dir = test::scratchDir("rotation_count");
  RetentionLimits limits = smallLimits();
  limits.keepBytes = 1ull << 40;
  limits.keepSegments = 2;
  auto store = std::make_shared<SegmentStore>(dir, limits);
  {
    RotatingFile f(dir, "energy.jsonl", "per-frame energy log", "", store);
    for (int i = 0; i < 100; ++i) f.append(line(4096));   // 400 KiB: 7 segments
    CHECK(streamFiles(dir, "energy.jsonl").size() == 3);  // 2 closed + the current one
  }
  // Free space below the floor: every closed segment goes (the file system has less than a petabyte free).
  limits.keepSegments = 0;
  limits.minFreeBytes = 1ull << 50;
  auto tight = std::make_shared<SegmentStore>(dir, limits);
  RotatingFile f(dir, "energy.jsonl", "per-frame energy log", "", tight);
  f.append("{}\n");
  CHECK(streamFiles(dir, "energy.jsonl") == std::vector<std::string>{f.path()});
  CHECK(tight->usage().freeBytes < limits.minFreeBytes);
}

TEST_CASE("rotation by age", "[core][rotation]") {
  const std::string dir = test::scratchDir("rotation_age");
  RetentionLimits limits = smallLimits();
  limits.segmentSeconds = 0.05;
  auto store = std::make_shared<SegmentStore>(dir, limits);
  RotatingFile f(dir, "power.csv", "power trace", "# meter\nt_ns,watts\n", store);
  f.append("1,2\n");
  std::this_thread::sleep_for(std::chrono::milliseconds(80));
  f.append("3,4\n");
  CHECK(f.segment() == 2);
  CHECK(test::readText(f.path()) == "# meter\nt_ns,watts\n3,4\n");
}

TEST_CASE("retention limits are validated with what to do", "[core][rotation]") {
  RetentionLimits l = smallLimits();
  l.keepBytes = 4 * kSegment;
  CHECK_THROWS_WITH(validateRetention(l),
                    Catch::Contains("less than 8 segments") && Catch::Contains("raise"));
  l = smallLimits();
  l.segmentBytes = 1000;
  CHECK_THROWS_WITH(validateRetention(l), Catch::Contains("64 KiB"));
  CHECK_NOTHROW(validateRetention(RetentionLimits{}));
}

TEST_CASE("a closed directory is one unit of retention: its segments join it and it goes whole",
          "[core][rotation]") {
  // A looping replay's pass directories (daemon/pass_directories.h): rotated segments and other files inside.
  const std::string dir = test::scratchDir("rotation_directories");
  RetentionLimits limits = smallLimits();  // 512 KiB kept
  auto store = std::make_shared<SegmentStore>(dir, limits);
  const auto pass = [&](int n) {
    const std::string passDir = dir + "/pass-000" + std::to_string(n);
    fs::create_directories(passDir);
    {
      RotatingFile f(passDir, "frames.jsonl", "per-frame log", "", store);
      for (int i = 0; i < 30; ++i) f.append(line(4096));  // 120 KiB: 2 segments
    }
    std::ofstream(passDir + "/summary.json") << std::string(10000, ' ') << "{}\n";
    store->addClosedDirectory(passDir, SegmentStore::nowOrder());
    return passDir;
  };
  const std::string first = pass(1);
  SegmentUsage u = store->usage();
  CHECK(u.segments == 1);  // the directory, not its two segments
  CHECK(u.bytes == bytesOf(streamFiles(first, "frames.jsonl")) + fs::file_size(first + "/summary.json"));
  for (int n = 2; n <= 6; ++n) pass(n);  // 6 x 130 KiB: past the 512 KiB limit
  u = store->usage();
  CHECK(u.bytes <= limits.keepBytes);
  CHECK(u.removedSegments >= 2);
  CHECK_FALSE(fs::exists(first));  // removed whole, oldest first
  CHECK(fs::exists(dir + "/pass-0006/summary.json"));
}

TEST_CASE("writeMakingRoom removes the oldest segments while a write finds the disk full",
          "[core][rotation]") {
  const std::string dir = test::scratchDir("rotation_making_room");
  auto store = std::make_shared<SegmentStore>(dir, smallLimits());
  {
    RotatingFile f(dir, "frames.jsonl", "per-frame log", "", store);
    for (int i = 0; i < 40; ++i) f.append(line(4096));  // 3 segments: 2 closed, then the third closes too
  }
  REQUIRE(streamFiles(dir, "frames.jsonl").size() == 3);
  int tries = 0;
  store->writeMakingRoom([&] {
    if (++tries <= 2) throw DiskFullError("disk full");  // the disk has room once two segments went
  });
  CHECK(tries == 3);
  CHECK(store->usage().removedSegments == 2);
  CHECK(streamFiles(dir, "frames.jsonl") == std::vector<std::string>{dir + "/frames-000003.jsonl"});
  // Nothing left to remove: the error goes to the caller. Other errors are never retried.
  CHECK_THROWS_AS(store->writeMakingRoom([] { throw DiskFullError("disk full"); }), DiskFullError);
  CHECK(store->usage().removedSegments == 3);
  tries = 0;
  CHECK_THROWS_WITH(store->writeMakingRoom([&] {
    ++tries;
    throw Error("permission denied");
  }),
                    "permission denied");
  CHECK(tries == 1);
}

namespace {

// Files another part owns (the moving volume's map slabs): ages given, the newest never removable.
class FakeAttached : public AttachedFiles {
 public:
  explicit FakeAttached(std::vector<int64_t> orders) : orders_(std::move(orders)) {}
  std::optional<int64_t> oldestRemovable() const override {
    if (orders_.size() < 2) return std::nullopt;
    return orders_.front();
  }
  uint64_t removeOldestAttached() override {
    removed.push_back(orders_.front());
    orders_.erase(orders_.begin());
    return 1;
  }
  std::vector<int64_t> removed;

 private:
  std::vector<int64_t> orders_;
};

// A store over an emptied `dir` holding two closed segments of one byte, dir/seg-10 and dir/seg-30 (orders 10
// and 30), for the attached files' tests to interleave with.
std::shared_ptr<SegmentStore> storeOfTwoSegments(const std::string& dir) {
  fs::remove_all(dir);
  fs::create_directories(dir);
  auto store = std::make_shared<SegmentStore>(dir, smallLimits());
  for (const int64_t order : {10, 30}) {
    const std::string path = dir + "/seg-" + std::to_string(order);
    std::ofstream(path) << "x";
    store->addClosed(path, 1, order);
  }
  return store;
}

}  // namespace

TEST_CASE("attached files give way to a full disk and the free-space floor with the segments, oldest first",
          "[core][rotation]") {
  const std::string dir = test::scratchDir("rotation_attached");
  auto store = storeOfTwoSegments(dir);
  FakeAttached slabs({20, 40, 50});  // 50: the newest, stays
  store->attach(&slabs);
  // Three writes find the disk full: the segment of 10, the slab of 20, the segment of 30 go, in that order.
  int tries = 0;
  store->writeMakingRoom([&] {
    if (++tries <= 3) throw DiskFullError("disk full");
  });
  CHECK(slabs.removed == std::vector<int64_t>{20});
  CHECK_FALSE(fs::exists(dir + "/seg-10"));
  CHECK_FALSE(fs::exists(dir + "/seg-30"));
  SegmentUsage u = store->usage();
  CHECK(u.removedSegments == 2);
  CHECK(u.removedAttached == 1);
  // The byte limit is the segments' alone: attached files never go for it.
  store->enforce();
  CHECK(slabs.removed == std::vector<int64_t>{20});
  // Below the free-space floor (no file system has a petabyte free) every removable one goes, the newest
  // slab stays.
  RetentionLimits tight = smallLimits();
  tight.minFreeBytes = 1ull << 50;
  auto floorStore = std::make_shared<SegmentStore>(dir, tight);
  floorStore->attach(&slabs);
  floorStore->enforce();
  CHECK(slabs.removed == std::vector<int64_t>{20, 40});
  CHECK_FALSE(slabs.oldestRemovable());
  // Detached: never touched again.
  FakeAttached other({1, 2});
  floorStore->attach(&other);
  floorStore->detach(&other);
  floorStore->enforce();
  CHECK(other.removed.empty());
  store->detach(&slabs);
  floorStore->detach(&slabs);
}

TEST_CASE("makeRoom frees room before a write: the oldest go while the free space is below the need",
          "[core][rotation]") {
  // Issue 44 M3: a map slab needs about twice its file's size while it is written; the store makes that room
  // first instead of letting the write fail.
  const std::string dir = test::scratchDir("rotation_make_room");
  auto store = storeOfTwoSegments(dir);
  FakeAttached slabs({20, 40});  // 40: the newest slab, stays
  store->attach(&slabs);
  store->makeRoom(1024);  // any file system has a KiB free: nothing goes
  CHECK(fs::exists(dir + "/seg-10"));
  CHECK(slabs.removed.empty());
  store->makeRoom(1ull << 50);  // no file system has a petabyte free: every removable one goes, oldest first
  CHECK_FALSE(fs::exists(dir + "/seg-10"));
  CHECK_FALSE(fs::exists(dir + "/seg-30"));
  CHECK(slabs.removed == std::vector<int64_t>{20});
  CHECK(store->usage().removedAttached == 1);
  store->detach(&slabs);
}
