#include "runtime/line_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/disk_full.h"
#include "core/exclusive_file.h"

namespace sb {

LineFile::LineFile(const std::string& path, std::string what) : path_(path), what_(std::move(what)) {
  try {
    fd_ = createReplacing(path);
  } catch (const Error& e) {
    throw WriteError("cannot write " + what_ + ": " + e.what(), path);
  }
}

LineFile::LineFile(UniqueFd fd, const std::string& path, std::string what)
    : fd_(std::move(fd)), path_(path), what_(std::move(what)) {}

void LineFile::append(std::string_view lines) {
  size_t done = 0;
  while (done < lines.size()) {
    const ssize_t n =
        ::pwrite(fd_.get(), lines.data() + done, lines.size() - done, size_ + static_cast<off_t>(done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error = n < 0 ? errno : ENOSPC;
      (void)!::ftruncate(fd_.get(), size_);  // drop the part line: the file stays whole lines
      const std::string message = "writing " + what_ + " '" + path_ + "' failed: " + std::strerror(error) +
                                  "; the file keeps the lines before it (free disk space and run again)";
      throwWriteFailure(message, path_, error);
    }
    done += static_cast<size_t>(n);
  }
  size_ += static_cast<off_t>(done);
}

}  // namespace sb
