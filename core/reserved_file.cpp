#include "core/reserved_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/disk_full.h"
#include "core/exclusive_file.h"

namespace sb {

ReservedFile::ReservedFile(const std::string& target, uint64_t bytes)
    : target_(target), file_(std::make_unique<TemporaryFile>(target, ".reserve")) {
  const int error = ::posix_fallocate(file_->fd(), 0, static_cast<off_t>(bytes));  // returns the error
  if (error != 0)
    throwWriteFailure("cannot keep " + std::to_string(bytes) + " bytes aside for the last write of '" +
                          target + "' ('" + file_->path() + "'): " + std::strerror(error) +
                          " (free disk space and start again)",
                      target, error);
  bytes_ = bytes;
}

ReservedFile::~ReservedFile() = default;  // an unused reserve is removed by its TemporaryFile

bool ReservedFile::grow(uint64_t bytes) {
  if (!file_) return false;
  if (bytes <= bytes_) return true;
  if (::posix_fallocate(file_->fd(), 0, static_cast<off_t>(bytes)) != 0) return false;
  bytes_ = bytes;
  return true;
}

void ReservedFile::replaceTarget(std::string_view content) {
  if (!file_)
    throw WriteError("the room kept aside for '" + target_ + "' was used already; free disk space", target_);
  // Into the blocks allocated at the start (no new block while the content fits), then cut to its length.
  const int fd = file_->fd();
  size_t done = 0;
  while (done < content.size()) {
    const ssize_t n = ::pwrite(fd, content.data() + done, content.size() - done, static_cast<off_t>(done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error = n < 0 ? errno : ENOSPC;
      throwWriteFailure("writing '" + target_ + "' into the room kept aside for it ('" + file_->path() +
                            "', " + std::to_string(bytes_) + " bytes, " + std::to_string(content.size()) +
                            " needed) failed: " + std::strerror(error) + "; '" + target_ +
                            "' keeps what it had (free disk space)",
                        target_, error);
    }
    done += static_cast<size_t>(n);
  }
  if (::ftruncate(fd, static_cast<off_t>(content.size())) != 0) {
    const int error = errno;
    throwWriteFailure(
        "cannot cut '" + file_->path() + "' to the length of '" + target_ + "': " + std::strerror(error),
        target_, error);
  }
  try {
    file_->commit();
  } catch (const Error& e) {
    throw WriteError(e.what(), target_);
  }
  file_.reset();
  bytes_ = 0;
}

}  // namespace sb
