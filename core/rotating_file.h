#pragma once
// An output file of whole lines for runs of any length. Without a segment store it is one file, DIR/NAME,
// created (truncated) at the start: what a replay writes. With a store (core/segment_store.h) it is a series
// of segments DIR/STEM-000001EXT, DIR/STEM-000002EXT, ... (frames.jsonl -> frames-000001.jsonl): a new
// segment starts when the current one reaches the store's size or age limit, each segment starts with the
// header, and the store removes the oldest segments to keep the directory within its limits. Numbering goes
// on from the highest segment already in the directory (a restarted daemon never overwrites one), and the
// segments already there join the store's retention. Reading a stream back: streamFiles().
//
// Each append() is one write(2) straight to the file (no user-space buffer), so a killed process leaves every
// line it finished and none in part. A failed or short write is cut back to the last whole line; with a
// store, a full disk (ENOSPC) removes the oldest segment and writes again (as a last resort the current
// segment is closed and removed), so the service goes on; otherwise it throws sb::Error naming the file.
//
// One thread writes a RotatingFile; the store may be shared.

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/segment_store.h"
#include "core/unique_fd.h"

namespace sb {

static_assert(
    sizeof(off_t) == 8,
    "off_t is 32 bits: outputs past 2 GiB would fail; build with -D_FILE_OFFSET_BITS=64 (the top-level "
    "CMakeLists.txt sets it)");

class RotatingFile {
 public:
  // `what` names the output in errors ("per-frame log"); `header` (whole lines, may be empty) starts the file
  // and, with a store, every segment. Throws sb::Error naming the file when it cannot be created.
  RotatingFile(const std::string& dir, const std::string& name, std::string what, std::string header = "",
               std::shared_ptr<SegmentStore> store = nullptr);
  ~RotatingFile();  // the current segment is handed to the store's retention
  RotatingFile(const RotatingFile&) = delete;
  RotatingFile& operator=(const RotatingFile&) = delete;

  // Appends `lines` (one or more, each ending in '\n') with one write. Throws sb::Error on failure.
  void append(std::string_view lines);
  // fsync of the current file. Throws sb::Error naming it.
  void sync();
  // The file being written now.
  const std::string& path() const { return path_; }
  // 1-based number of the current segment (0 without a store).
  uint64_t segment() const { return segment_; }
  // The files this writer wrote that are still on disk, oldest first (retention may have removed some).
  std::vector<std::string> files() const;
  // Segments removed to make room after a write failed for lack of space.
  uint64_t spaceRecoveries() const { return spaceRecoveries_; }

 private:
  void openSegment();
  void rotate();
  bool due() const;
  void write(std::string_view data);
  int writeOnce(std::string_view data);  // 0, or the errno of a failed write (the file cut back)

  std::string dir_, stem_, ext_, what_, header_;
  std::shared_ptr<SegmentStore> store_;
  UniqueFd fd_;
  std::string path_;
  off_t size_ = 0;  // bytes of whole lines in the current file
  uint64_t segment_ = 0;
  uint64_t firstSegment_ = 0;  // this writer's first
  uint64_t spaceRecoveries_ = 0;
  std::chrono::steady_clock::time_point opened_;
};

// The files of stream NAME in DIR in the order they were written: its segments (STEM-NNNNNNEXT, by number)
// when there are any, else DIR/NAME when it exists, else none.
std::vector<std::string> streamFiles(const std::string& dir, const std::string& name);
// The segment file name of stream `name` ("frames.jsonl", 7 -> "frames-000007.jsonl").
std::string segmentName(const std::string& name, uint64_t segment);

}  // namespace sb
