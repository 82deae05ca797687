// Files nobody else can redirect (core/exclusive_file.h, issue 44 S3): a temporary is a new file of its own
// name, never a name made beforehand; commit() renames it over the target (replacing a symlink, not writing
// through it); an uncommitted one is removed; createReplacing() replaces a symlink or hard link; a symlinked
// subdirectory is refused.

#include <fcntl.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/exclusive_file.h"
#include "tests/support/files.h"
#include "tests/support/test_data.h"

using namespace sb;
namespace fs = std::filesystem;

namespace {

size_t entries(const std::string& dir) {
  size_t n = 0;
  for (const auto& e : fs::directory_iterator(dir)) n += !e.path().empty();
  return n;
}

}  // namespace

TEST_CASE("a temporary is a new file, renamed over its target; links planted beforehand are not followed",
          "[core][exclusive]") {
  const std::string dir = test::scratchDir("exclusive_temporary");
  std::ofstream(dir + "/victim") << "victim\n";
  fs::create_symlink(dir + "/victim", dir + "/out.json.tmp");  // the old fixed temporary name
  fs::create_symlink(dir + "/victim", dir + "/out.json");      // the target itself
  {
    TemporaryFile tmp(dir + "/out.json");
    CHECK(tmp.path() != dir + "/out.json.tmp");
    CHECK(tmp.path().rfind(dir + "/out.json.tmp.", 0) == 0);
    std::fputs("new\n", tmp.stream());
    tmp.commit();
  }
  CHECK(test::readText(dir + "/victim") == "victim\n");
  CHECK(fs::is_regular_file(fs::symlink_status(dir + "/out.json")));
  CHECK(test::readText(dir + "/out.json") == "new\n");
  // Uncommitted: removed. writeFileAtomically: the same, and a throwing writer leaves the target as it was.
  { TemporaryFile dropped(dir + "/other"); }
  CHECK(entries(dir) == 3);  // victim, out.json.tmp (the planted link), out.json
  CHECK_THROWS(writeFileAtomically(dir + "/out.json", [](std::FILE*, const std::string&) { throw Error("no"); }));
  CHECK(test::readText(dir + "/out.json") == "new\n");
  CHECK(entries(dir) == 3);
}

TEST_CASE("createReplacing replaces a symlink or a hard link, never writes through it", "[core][exclusive]") {
  const std::string dir = test::scratchDir("exclusive_replacing");
  std::ofstream(dir + "/victim") << "victim\n";
  fs::create_symlink(dir + "/victim", dir + "/soft");
  fs::create_hard_link(dir + "/victim", dir + "/hard");
  fs::create_symlink(dir + "/absent", dir + "/dangling");
  for (const char* name : {"soft", "hard", "dangling"}) {
    UniqueFd fd = createReplacing(dir + "/" + name);
    REQUIRE(::write(fd.get(), "x\n", 2) == 2);
    CHECK(test::readText(dir + "/" + name) == "x\n");
  }
  CHECK(test::readText(dir + "/victim") == "victim\n");
  CHECK_FALSE(fs::exists(dir + "/absent"));
}

TEST_CASE("openOwnSubdirectory makes a directory and refuses a symlink", "[core][exclusive]") {
  const std::string dir = test::scratchDir("exclusive_subdirectory");
  fs::create_directories(dir + "/elsewhere");
  const UniqueFd parent = openDirectory(dir);
  CHECK(openOwnSubdirectory(parent.get(), dir, "own").valid());
  CHECK(fs::is_directory(dir + "/own"));
  fs::create_directory_symlink(dir + "/elsewhere", dir + "/linked");
  CHECK_THROWS_WITH(openOwnSubdirectory(parent.get(), dir, "linked"), Catch::Contains("is a symlink"));
}
