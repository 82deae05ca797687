#include "daemon/pass_directories.h"

#include <sys/stat.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace sb::daemon {

namespace {

constexpr const char* kPrefix = "pass-";
constexpr size_t kMaxDigits = 9;

int64_t modifiedNs(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return 0;
  return static_cast<int64_t>(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
}

}  // namespace

uint64_t passNumber(const std::string& name) {
  const std::string prefix = kPrefix;
  if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) return 0;
  const std::string digits = name.substr(prefix.size());
  if (digits.size() > kMaxDigits || digits.find_first_not_of("0123456789") != std::string::npos) return 0;
  return std::stoull(digits);
}

PassDirectories::PassDirectories(std::string outputDir, std::shared_ptr<SegmentStore> store)
    : outputDir_(std::move(outputDir)), store_(std::move(store)) {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(outputDir_, ec)) {
    const uint64_t n = passNumber(entry.path().filename().string());
    if (n == 0) continue;
    last_ = std::max(last_, n);  // a file of that name too: the next pass takes another
    if (store_ && entry.is_directory(ec))
      store_->addClosedDirectory(entry.path().string(), modifiedNs(entry.path().string()));
  }
}

std::string PassDirectories::next() {
  char name[32];
  std::snprintf(name, sizeof name, "%s%04llu", kPrefix, static_cast<unsigned long long>(++last_));
  return (std::filesystem::path(outputDir_) / name).string();
}

void PassDirectories::close(const std::string& dir) {
  if (store_) store_->addClosedDirectory(dir, SegmentStore::nowOrder());
}

}  // namespace sb::daemon
