#pragma once
// An output file of whole lines that survives crashes and full disks in a known state: each append() is one
// write(2) straight to the file (no user-space buffer), so a killed process leaves every line it finished
// and none in part; a failed or short write (disk full, I/O error) is cut back to the last whole line and
// throws sb::Error naming the file (sb::DiskFullError when the disk is full), so the file stays a
// line-complete prefix of the run.

#include <sys/types.h>

#include <string>
#include <string_view>

#include "core/unique_fd.h"

namespace sb {

class LineFile {
 public:
  // Creates `path` anew (core/exclusive_file.h createReplacing: a symlink or hard link of that name is
  // replaced, never written through). `what` names the file in errors ("trajectory", "per-frame log").
  LineFile(const std::string& path, std::string what);
  // Writes to `fd` (an empty file opened for writing, e.g. a TemporaryFile's), named `path` in errors.
  LineFile(UniqueFd fd, const std::string& path, std::string what);
  // Appends `lines` (one or more, each ending in '\n') with one write. Throws sb::DiskFullError when the
  // disk is full, sb::Error on any other failure.
  void append(std::string_view lines);
  const std::string& path() const { return path_; }

 private:
  UniqueFd fd_;
  std::string path_, what_;
  off_t size_ = 0;  // bytes of whole lines on disk
};

}  // namespace sb
