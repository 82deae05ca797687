#include "tests/support/test_data.h"

#include <cstdlib>
#include <filesystem>

namespace fs = std::filesystem;

namespace sb::test {

std::string sharedDataDir() {
  if (const char* env = std::getenv("SB_SHARED_DATA")) return env;
  return SB_SHARED_DATA_DIR;
}

bool hasSharedData(const std::string& sub) {
  std::error_code ec;
  return fs::is_directory(fs::path(sharedDataDir()) / sub, ec);
}

std::string testBinary(const char* env, const std::string& built) {
  const char* value = std::getenv(env);
  return value && *value ? std::string(value) : built;
}

std::string scratchDir(const std::string& name) {
  const fs::path dir = fs::path(SB_TEST_SCRATCH_DIR) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

}  // namespace sb::test
