#include "core/segment_store.h"

#include <sys/stat.h>
#include <sys/statvfs.h>

#include <chrono>
#include <filesystem>

#include "core/disk_full.h"
#include "core/error.h"

namespace sb {

namespace {

constexpr uint64_t kMinSegmentBytes = 64ull << 10;
constexpr uint64_t kStreamsPerDir = 4;  // trajectory, frames, energy, power trace: each has a current segment

}  // namespace

void validateRetention(const RetentionLimits& l) {
  if (l.segmentBytes < kMinSegmentBytes)
    throw Error("retention: segment size " + std::to_string(l.segmentBytes) +
                " bytes is below the minimum of " + std::to_string(kMinSegmentBytes) + " (64 KiB)");
  if (!(l.segmentSeconds >= 0.0))
    throw Error("retention: segment age must be >= 0 s (0 = rotate by size only)");
  if (l.keepBytes < 2 * kStreamsPerDir * l.segmentBytes)
    throw Error("retention: keep " + std::to_string(l.keepBytes) + " bytes is less than 8 segments (" +
                std::to_string(2 * kStreamsPerDir * l.segmentBytes) +
                " bytes): the current segments of the four streams alone could pass it; raise the limit or "
                "lower the segment size");
}

SegmentStore::SegmentStore(std::string dir, const RetentionLimits& limits)
    : dir_(std::move(dir)), limits_(limits) {
  validateRetention(limits_);
}

int64_t SegmentStore::nowOrder() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

int64_t SegmentStore::modifiedOrder(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return 0;
  return static_cast<int64_t>(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
}

void SegmentStore::addClosed(const std::string& path, uint64_t bytes, int64_t order) {
  {
    std::lock_guard lock(mutex_);
    closed_.emplace(order, std::make_pair(path, bytes));
    closedBytes_ += bytes;
  }
  enforce();
}

void SegmentStore::addClosedDirectory(const std::string& dir, int64_t order) {
  namespace fs = std::filesystem;
  const std::string root = fs::path(dir).lexically_normal().string();
  uint64_t bytes = 0;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(root, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    std::error_code sizeError;
    if (it->is_regular_file(sizeError)) {
      const uintmax_t size = it->file_size(sizeError);
      if (!sizeError) bytes += size;
    }
  }
  {
    std::lock_guard lock(mutex_);
    const std::string prefix = root + "/";
    for (auto it = closed_.begin(); it != closed_.end();) {
      const std::string path = fs::path(it->second.first).lexically_normal().string();
      if (path.compare(0, prefix.size(), prefix) == 0) {
        closedBytes_ -= it->second.second;
        it = closed_.erase(it);
      } else {
        ++it;
      }
    }
    closed_.emplace(order, std::make_pair(root, bytes));
    closedBytes_ += bytes;
  }
  enforce();
}

void SegmentStore::setCurrent(const void* writer, uint64_t bytes) {
  std::lock_guard lock(mutex_);
  current_[writer] = bytes;
}

void SegmentStore::reserve(const void* writer, uint64_t bytes) {
  std::lock_guard lock(mutex_);
  current_[writer] = bytes;
  enforceLimitsLocked();
}

void SegmentStore::dropCurrent(const void* writer) {
  std::lock_guard lock(mutex_);
  current_.erase(writer);
}

uint64_t SegmentStore::totalLocked() const {
  uint64_t total = closedBytes_;
  for (const auto& c : current_) total += c.second;
  return total;
}

uint64_t SegmentStore::freeBytesLocked() const {
  struct statvfs fs {};
  if (::statvfs(dir_.c_str(), &fs) != 0) return UINT64_MAX;  // unknown: no removal for space
  return static_cast<uint64_t>(fs.f_bavail) * static_cast<uint64_t>(fs.f_frsize);
}

bool SegmentStore::removeOldestLocked() {
  if (closed_.empty()) return false;
  const auto oldest = closed_.begin();
  std::error_code ec;
  // A segment file or a closed directory; already gone (removed by hand): forget it all the same.
  std::filesystem::remove_all(oldest->second.first, ec);
  closedBytes_ -= oldest->second.second;
  removedBytes_ += oldest->second.second;
  ++removedSegments_;
  closed_.erase(oldest);
  return true;
}

bool SegmentStore::removeOldestForSpaceLocked() {
  // The oldest of every kind: a closed segment, or an attached file that may go.
  AttachedFiles* oldestAttached = nullptr;
  int64_t oldestOrder = 0;
  for (AttachedFiles* files : attached_) {
    const std::optional<int64_t> order = files->oldestRemovable();
    if (order && (!oldestAttached || *order < oldestOrder)) {
      oldestAttached = files;
      oldestOrder = *order;
    }
  }
  if (oldestAttached && (closed_.empty() || oldestOrder < closed_.begin()->first)) {
    oldestAttached->removeOldestAttached();
    ++removedAttached_;
    return true;
  }
  return removeOldestLocked();
}

bool SegmentStore::removeOldest() {
  std::lock_guard lock(mutex_);
  return removeOldestForSpaceLocked();
}

void SegmentStore::attach(AttachedFiles* files) {
  std::lock_guard lock(mutex_);
  attached_.insert(files);
}

void SegmentStore::detach(AttachedFiles* files) {
  std::lock_guard lock(mutex_);
  attached_.erase(files);
}

void SegmentStore::writeMakingRoom(const std::function<void()>& write) {
  while (true) {
    try {
      write();
      return;
    } catch (const DiskFullError&) {
      if (!removeOldest()) throw;
    }
  }
}

void SegmentStore::makeRoom(uint64_t bytes) {
  std::lock_guard lock(mutex_);
  while (bytes > 0 && freeBytesLocked() < bytes && removeOldestForSpaceLocked()) {
  }
}

void SegmentStore::enforceLimitsLocked() {
  while (totalLocked() > limits_.keepBytes && removeOldestLocked()) {
  }
  while (limits_.keepSegments > 0 && closed_.size() > limits_.keepSegments && removeOldestLocked()) {
  }
}

void SegmentStore::enforce() {
  std::lock_guard lock(mutex_);
  enforceLimitsLocked();
  // The free space after every write (one statvfs, about a microsecond): another program may fill the disk at
  // any moment, and the outputs that do not rotate (summary.json, rewritten every frame) need room too.
  while (limits_.minFreeBytes > 0 && freeBytesLocked() < limits_.minFreeBytes &&
         removeOldestForSpaceLocked()) {
  }
}

SegmentUsage SegmentStore::usage() const {
  std::lock_guard lock(mutex_);
  SegmentUsage u;
  u.bytes = totalLocked();
  u.segments = closed_.size() + current_.size();
  u.removedSegments = removedSegments_;
  u.removedBytes = removedBytes_;
  u.freeBytes = freeBytesLocked();
  u.keepBytes = limits_.keepBytes;
  u.removedAttached = removedAttached_;
  return u;
}

}  // namespace sb
