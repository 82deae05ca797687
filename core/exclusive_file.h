#pragma once
// Files in an output directory that nobody else can redirect (issue 44 S3). Anyone who can create files in
// an output directory can make a name there beforehand, as a symlink or a hard link to a file elsewhere; a
// process that opens that name with O_CREAT|O_TRUNC writes through it. So:
//
// - a temporary (the file that becomes summary.json, model.png, mesh.ply, a map slab, report.html) is created
//   under a name of its own that did not exist before ("<name><tag>.<random>"), with
//   O_CREAT|O_EXCL|O_NOFOLLOW through the directory's descriptor, written through that descriptor, and renamed
//   over its name (rename replaces a symlink itself, never its target);
// - an output written in place (trajectory.tum, frames.jsonl, energy.jsonl, their segments) is opened without
//   following a symlink and looked at through its descriptor before anything is truncated: a symlink or a
//   file with other hard links there is unlinked (the file it pointed at stays as it was) and the name created
//   anew with O_CREAT|O_EXCL|O_NOFOLLOW; a file of one link is truncated; a device is written as it is.
// A name that is made again between the two steps fails with an error naming it; nothing is followed.

#include <cstdio>
#include <memory>
#include <string>

#include "core/unique_fd.h"

namespace sb {

// The directory `path` (a symlink to a directory is followed: the operator names it), O_DIRECTORY|O_CLOEXEC.
// Throws sb::Error naming it.
UniqueFd openDirectory(const std::string& path);

// The subdirectory `name` of the directory `parent` (at `parentPath`, for messages), made (0755) when absent.
// A `name` that is a symlink, or anything but a directory, is refused (sb::Error naming it): what is written
// and removed there stays inside `parent`.
UniqueFd openOwnSubdirectory(int parent, const std::string& parentPath, const std::string& name);

// DIR/NAME as an empty file for writing (0644 less the umask when made): never through a symlink or into a
// file with other hard links (those are replaced); a device stays a device. Throws sb::Error naming the file.
UniqueFd createReplacing(const std::string& path);
UniqueFd createReplacing(int dir, const std::string& dirPath, const std::string& name);

// A new file beside `target` that becomes `target` on commit(), or is removed when destroyed uncommitted.
class TemporaryFile {
 public:
  // Beside `target` (a path): "<target><tag>.<random>". Throws sb::Error naming the directory.
  explicit TemporaryFile(const std::string& target, const std::string& tag = ".tmp");
  // Inside the open directory `dir` (at `dirPath`, for messages), for the name `targetName`.
  TemporaryFile(int dir, const std::string& dirPath, const std::string& targetName, const std::string& tag);
  ~TemporaryFile();
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;

  // Read-write descriptor of the file.
  int fd() const { return fd_.get(); }
  // A stdio stream on it ("w+b"), made on first use and owned here.
  std::FILE* stream();
  // The temporary's path, for messages.
  const std::string& path() const { return path_; }
  // Flushes and closes the stream (a write error throws sb::Error, with DiskFullError for ENOSPC/EDQUOT),
  // then renames the file over its target. Throws sb::Error naming both.
  void commit();

 private:
  void create(const std::string& tag);

  UniqueFd dir_, fd_;
  std::string dirPath_, targetName_, name_, path_;
  std::FILE* stream_ = nullptr;
  bool committed_ = false;
};

}  // namespace sb
