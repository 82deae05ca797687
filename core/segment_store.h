#pragma once
// The retention of rotated outputs (core/rotating_file.h): every closed segment of the rotating files of one
// output directory, with their sizes, and the limits that bound them. When the segments together pass the
// byte or count limit, or the file system's free space falls below its floor, the oldest closed segments are
// removed first, across all streams (so every stream keeps about the same span of time). A full disk is
// handled the same way: a write that fails with ENOSPC removes the oldest segment and tries again.
// A closed unit may also be a whole directory (a looping replay's pass directory, daemon/pass_directories.h):
// it counts once, with every file under it, and is removed whole.
// Files another part owns and bounds by its own limit (the moving volume's map slabs, runtime/map_slabs.h)
// can be attached (AttachedFiles): the free-space floor and a full disk remove them with the segments, the
// oldest of either first; the byte and count limits (and usage's bytes) are the segments' alone.
//
// Shared by the threads that write rotating files (the SLAM thread, the power sampler) and read for STATUS
// (the event loop): every method is thread-safe.
//
//   auto store = std::make_shared<SegmentStore>(dir, RetentionLimits{});   // limits validated
//   RotatingFile frames(dir, "frames.jsonl", "per-frame log", "", store);
//   store->usage();   // bytes on disk, segments, free space

#include <sys/types.h>

#include <cstddef>
#include <cstdint>
#include <ctime>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>

namespace sb {

static_assert(
    sizeof(time_t) == 8,
    "time_t is 32 bits: file times (the age order of segments) end in 2038; build with -D_TIME_BITS=64 "
    "(the top-level CMakeLists.txt sets it on 32-bit targets)");

// How long rotated outputs live. Sizes in bytes, times in seconds; 0 turns a limit off where it says so.
struct RetentionLimits {
  uint64_t segmentBytes = 64ull << 20;   // a stream starts a new segment once its current one holds this much
  double segmentSeconds = 3600.0;        // ... or is this old (s); 0 = by size only
  uint64_t keepBytes = 4ull << 30;       // every segment of the directory together (current ones included)
  size_t keepSegments = 0;               // closed segments kept at most (0 = no count limit)
  uint64_t minFreeBytes = 512ull << 20;  // oldest segments go while the file system has less free space
};

// Throws sb::Error naming the limit and what is allowed (keepBytes below 8 segments: the four per-frame
// streams' current segments alone could pass it).
void validateRetention(const RetentionLimits& limits);

// What the segments take (STATUS "disk").
struct SegmentUsage {
  uint64_t bytes = 0;            // closed and current segments
  size_t segments = 0;           // closed and current
  uint64_t removedSegments = 0;  // removed by retention since the store was made
  uint64_t removedBytes = 0;
  uint64_t freeBytes = 0;  // available to this process on the directory's file system
  uint64_t keepBytes = 0;  // the limit
  uint64_t removedAttached = 0;  // attached files (AttachedFiles) removed for space since the store was made
};

// Files of the output directory that another part writes and bounds itself (the moving volume's map slabs),
// attached to a SegmentStore so that they give way to the free-space floor and a full disk like the segments.
// The store calls these with its lock held, from any thread that writes: they must not call the store.
class AttachedFiles {
 public:
  virtual ~AttachedFiles() = default;
  // The age (SegmentStore::nowOrder's scale, or a file's modification time in ns) of the oldest file that may
  // be removed; none when none may (the newest slab always stays).
  virtual std::optional<int64_t> oldestRemovable() const = 0;
  // Removes that file (one already gone is forgotten all the same); returns its bytes.
  virtual uint64_t removeOldestAttached() = 0;
};

class SegmentStore {
 public:
  // `dir`: the output directory (its file system's free space is watched). Validates `limits`.
  SegmentStore(std::string dir, const RetentionLimits& limits);

  const RetentionLimits& limits() const { return limits_; }
  const std::string& dir() const { return dir_; }

  // A closed segment (written to its end); `order` sorts segments from oldest (smallest) to newest.
  void addClosed(const std::string& path, uint64_t bytes, int64_t order);
  // A closed directory (every file under it written): one unit of retention, with the bytes of every file
  // under it, removed whole. The closed segments already added from inside it become part of it.
  void addClosedDirectory(const std::string& dir, int64_t order);
  // The current size of the segment a writer has open (`writer`: any id unique to it, e.g. its address).
  void setCurrent(const void* writer, uint64_t bytes);
  void dropCurrent(const void* writer);
  // Before a writer grows its segment to `bytes`: accounts them and removes the oldest closed segments while
  // the byte or count limit would be passed, in one step, so the files on disk stay within the limits while
  // the write happens (enforce() after it would leave them over the limit for the time of the write).
  void reserve(const void* writer, uint64_t bytes);
  // Removes the oldest closed segments while a limit is passed (the free space is read each time). Called
  // after every write.
  void enforce();
  // Removes the oldest closed segment or attached file (a write failed for lack of space); false when there
  // is none.
  bool removeOldest();
  // Calls `write`, and again after removing the oldest closed segment or attached file for as long as it
  // throws sb::DiskFullError (core/disk_full.h) and a segment is left; then the error goes to the caller. For
  // the outputs that do not rotate but must go on when the disk fills (summary.json, rewritten every frame).
  void writeMakingRoom(const std::function<void()>& write);
  // Before a write of about `bytes`: removes the oldest closed segments or attached files while the file
  // system has less free space than that (and some are left). A map slab needs about twice its file's size
  // while it is written (runtime/map_slabs.h).
  void makeRoom(uint64_t bytes);
  SegmentUsage usage() const;
  // `files` are removed for space (with the segments, oldest first) until detached (before they are
  // destroyed).
  void attach(AttachedFiles* files);
  void detach(AttachedFiles* files);
  // A number that orders segments closed now after every earlier one (nanoseconds of the wall clock).
  static int64_t nowOrder();
  // The same for a file already on disk: its modification time (0 when it cannot be read).
  static int64_t modifiedOrder(const std::string& path);

 private:
  bool removeOldestLocked();          // closed segments only (the byte and count limits)
  void enforceLimitsLocked();         // the byte and count limits
  bool removeOldestForSpaceLocked();  // the oldest closed segment or attached file
  uint64_t freeBytesLocked() const;
  uint64_t totalLocked() const;

  std::string dir_;
  RetentionLimits limits_;
  mutable std::mutex mutex_;
  std::multimap<int64_t, std::pair<std::string, uint64_t>> closed_;  // order -> (path, bytes)
  std::map<const void*, uint64_t> current_;
  uint64_t closedBytes_ = 0;
  uint64_t removedSegments_ = 0, removedBytes_ = 0;
  std::set<AttachedFiles*> attached_;
  uint64_t removedAttached_ = 0;
};

}  // namespace sb
