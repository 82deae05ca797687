// ReservedFile (core/reserved_file.h): the room kept aside for a file's last write holds that write when the
// disk is full, whole under the target's name; content beyond the room fails and the target keeps what it
// had; an unused reserve leaves nothing behind. A real full disk: a tmpfs (root only; a failure under CI, a
// warning elsewhere).

#include <fcntl.h>
#include <sys/mount.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/disk_full.h"
#include "core/reserved_file.h"
#include "tests/support/test_data.h"

namespace fs = std::filesystem;

namespace {

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> names(const std::string& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

// Takes every free page of the file system of `dir`.
void fillDisk(const std::string& path) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  REQUIRE(fd >= 0);
  const std::string block(4096, 'x');
  while (::write(fd, block.data(), block.size()) > 0) {
  }
  ::close(fd);
}

uint64_t freeBytes(const std::string& dir) {
  struct statvfs s {};
  REQUIRE(::statvfs(dir.c_str(), &s) == 0);
  return uint64_t(s.f_bavail) * s.f_frsize;
}

}  // namespace

TEST_CASE("the room kept aside holds the last write on a full disk", "[core][disk]") {
  if (::geteuid() != 0) {
    if (std::getenv("CI")) FAIL("not root: this test needs a tmpfs (mount)");
    WARN("skipped: not root, no tmpfs for a full disk");
    return;
  }
  const std::string dir = sb::test::scratchDir("reserved_file");
  ::umount2(dir.c_str(), MNT_DETACH);  // left over from a test run that was killed
  REQUIRE(::mount("tmpfs", dir.c_str(), "tmpfs", 0, "size=256k") == 0);
  struct Unmount {
    std::string dir;
    ~Unmount() { ::umount2(dir.c_str(), MNT_DETACH); }
  } unmount{dir};
  const std::string target = dir + "/summary.json";
  std::ofstream(target) << "the old summary\n";

  {  // Unused: nothing left beside the target.
    sb::ReservedFile reserve(target, 16 << 10);
    CHECK(reserve.bytes() == 16 << 10);
    CHECK(names(dir).size() == 2);
  }
  CHECK(names(dir) == std::vector<std::string>{"summary.json"});

  sb::ReservedFile reserve(target, 16 << 10);
  CHECK(reserve.grow(32 << 10));
  CHECK(reserve.bytes() == 32 << 10);
  fillDisk(dir + "/filler");
  REQUIRE(freeBytes(dir) == 0);
  CHECK_FALSE(reserve.grow(64 << 10));  // best effort: the disk is full, the room kept stays
  CHECK(reserve.bytes() == 32 << 10);
  CHECK_THROWS_AS(sb::ReservedFile(dir + "/other.json", 16 << 10), sb::DiskFullError);  // said at the start

  // Larger than the room on a full disk: refused, naming the target; the target keeps what it had.
  const std::string tooLarge((64 << 10), 'y');
  try {
    reserve.replaceTarget(tooLarge);
    FAIL("content beyond the room was written on a full disk");
  } catch (const sb::DiskFullError& e) {
    CHECK(e.file() == target);
  }
  CHECK(readText(target) == "the old summary\n");

  // Within the room: written whole under the target's name, nothing left aside; once only.
  const std::string text = "{\"complete\": false, \"error\": \"No space left on device\"}\n";
  reserve.replaceTarget(text);
  CHECK(readText(target) == text);
  CHECK(reserve.bytes() == 0);
  CHECK(names(dir) == std::vector<std::string>{"filler", "summary.json"});
  CHECK_THROWS_AS(reserve.replaceTarget(text), sb::WriteError);
}
