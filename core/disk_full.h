#pragma once
// A write that failed, naming the file it was writing (WriteError::file(): the output as its writer names
// it, e.g. DIR/frames.jsonl, DIR/map_slabs/slab-000003.ply, DIR/summary.json; the final name, not a
// temporary), so that a run that ends on it can say which output failed (summary.json "error_file").
// DiskFullError: the file system is full (ENOSPC) or the quota is spent (EDQUOT); the retention of rotated
// outputs (core/segment_store.h: SegmentStore::writeMakingRoom) catches it, removes the oldest segment and
// writes again; anywhere else it is an sb::Error like any other.

#include <cerrno>
#include <string>

#include "core/error.h"

namespace sb {

class WriteError : public Error {
 public:
  WriteError(const std::string& what, std::string file) : Error(what), file_(std::move(file)) {}
  // The file whose write failed ("" when the writer did not say).
  const std::string& file() const { return file_; }

 private:
  std::string file_;
};

class DiskFullError : public WriteError {
 public:
  explicit DiskFullError(const std::string& what, std::string file = "")
      : WriteError(what, std::move(file)) {}
};

// The error of a write of `file` that failed with `errnum`: DiskFullError for ENOSPC and EDQUOT, else
// WriteError.
[[noreturn]] inline void throwWriteFailure(const std::string& what, const std::string& file, int errnum) {
  if (errnum == ENOSPC || errnum == EDQUOT) throw DiskFullError(what, file);
  throw WriteError(what, file);
}

}  // namespace sb
