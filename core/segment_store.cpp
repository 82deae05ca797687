#include "core/segment_store.h"

#include <sys/statvfs.h>

#include <algorithm>
#include <chrono>
#include <filesystem>

#include "core/error.h"

namespace sb {

namespace {

// Bytes written between two reads of the free space: half the room left above the floor, within these bounds
// (near the floor every few KiB, so that the outputs that do not rotate, such as summary.json, find room too).
constexpr uint64_t kMinFreeCheckBytes = 4ull << 10;
constexpr uint64_t kMaxFreeCheckBytes = 1ull << 20;
constexpr uint64_t kMinSegmentBytes = 64ull << 10;
constexpr uint64_t kStreamsPerDir = 4;  // trajectory, frames, energy, power trace: each has a current segment

}  // namespace

void validateRetention(const RetentionLimits& l) {
  if (l.segmentBytes < kMinSegmentBytes)
    throw Error("retention: segment size " + std::to_string(l.segmentBytes) + " bytes is below the minimum of " +
                std::to_string(kMinSegmentBytes) + " (64 KiB)");
  if (!(l.segmentSeconds >= 0.0))
    throw Error("retention: segment age must be >= 0 s (0 = rotate by size only)");
  if (l.keepBytes < 2 * kStreamsPerDir * l.segmentBytes)
    throw Error("retention: keep " + std::to_string(l.keepBytes) + " bytes is less than 8 segments (" +
                std::to_string(2 * kStreamsPerDir * l.segmentBytes) +
                " bytes): the current segments of the four streams alone could pass it; raise the limit or "
                "lower the segment size");
}

SegmentStore::SegmentStore(std::string dir, const RetentionLimits& limits) : dir_(std::move(dir)), limits_(limits) {
  validateRetention(limits_);
}

int64_t SegmentStore::nowOrder() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

void SegmentStore::addClosed(const std::string& path, uint64_t bytes, int64_t order) {
  {
    std::lock_guard lock(mutex_);
    closed_.emplace(order, std::make_pair(path, bytes));
    closedBytes_ += bytes;
  }
  enforce(true);
}

void SegmentStore::setCurrent(const void* writer, uint64_t bytes) {
  std::lock_guard lock(mutex_);
  current_[writer] = bytes;
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
  std::filesystem::remove(oldest->second.first, ec);  // already gone (removed by hand): forget it all the same
  closedBytes_ -= oldest->second.second;
  removedBytes_ += oldest->second.second;
  ++removedSegments_;
  closed_.erase(oldest);
  return true;
}

bool SegmentStore::removeOldest() {
  std::lock_guard lock(mutex_);
  return removeOldestLocked();
}

void SegmentStore::enforce(bool checkFree) {
  std::lock_guard lock(mutex_);
  while (totalLocked() > limits_.keepBytes && removeOldestLocked()) {
  }
  while (limits_.keepSegments > 0 && closed_.size() > limits_.keepSegments && removeOldestLocked()) {
  }
  const uint64_t total = totalLocked();
  if (checkFree || !freeChecked_ || total >= totalAtFreeCheck_ + freeCheckBytes_ || total < totalAtFreeCheck_) {
    uint64_t free = freeBytesLocked();
    while (free < limits_.minFreeBytes && removeOldestLocked()) free = freeBytesLocked();
    freeChecked_ = true;
    totalAtFreeCheck_ = totalLocked();
    const uint64_t room = free > limits_.minFreeBytes ? free - limits_.minFreeBytes : 0;
    freeCheckBytes_ = std::clamp(room / 2, kMinFreeCheckBytes, kMaxFreeCheckBytes);
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
  return u;
}

}  // namespace sb
