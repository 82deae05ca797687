#include "core/exclusive_file.h"

#include <fcntl.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <tuple>

#include "core/disk_full.h"
#include "core/error.h"

namespace sb {

namespace {

constexpr mode_t kFileMode = 0644;  // less the umask, as open(2) applies it
constexpr mode_t kDirectoryMode = 0755;
constexpr int kNameAttempts = 64;  // EEXIST on a random name this often means someone is guessing along

std::pair<std::string, std::string> splitPath(const std::string& path) {
  const size_t slash = path.rfind('/');
  if (slash == std::string::npos) return {".", path};
  return {slash == 0 ? "/" : path.substr(0, slash), path.substr(slash + 1)};
}

std::string join(const std::string& dir, const std::string& name) {
  return dir == "." ? name : (dir.back() == '/' ? dir + name : dir + "/" + name);
}

// Eight hex digits no other process can guess beforehand (getrandom, or the clock and a counter without it).
std::string randomSuffix() {
  static std::atomic<uint32_t> counter{0};
  uint32_t value = 0;
  if (::getrandom(&value, sizeof value, GRND_NONBLOCK) != static_cast<ssize_t>(sizeof value))
    value = static_cast<uint32_t>(std::chrono::steady_clock::now().time_since_epoch().count()) ^
            (counter.fetch_add(1) * 2654435761u) ^ static_cast<uint32_t>(::getpid());
  char text[16];
  std::snprintf(text, sizeof text, "%08x", value);
  return text;
}

int openExclusive(int dir, const std::string& name) {
  int fd;
  do {
    fd = ::openat(dir, name.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, kFileMode);
  } while (fd < 0 && errno == EINTR);
  return fd;
}

}  // namespace

UniqueFd openDirectory(const std::string& path) {
  UniqueFd dir(::open(path.empty() ? "." : path.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
  if (!dir.valid())
    throw Error("cannot open the directory '" + path + "': " + std::strerror(errno) +
                " (check that it exists and is writable)");
  return dir;
}

UniqueFd openOwnSubdirectory(int parent, const std::string& parentPath, const std::string& name) {
  const std::string path = join(parentPath, name);
  if (::mkdirat(parent, name.c_str(), kDirectoryMode) != 0 && errno != EEXIST)
    throw Error("cannot create '" + path + "': " + std::strerror(errno));
  UniqueFd dir(::openat(parent, name.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC));
  if (!dir.valid()) {
    const int error = errno;
    struct stat st {};
    const bool link = ::fstatat(parent, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0 && S_ISLNK(st.st_mode);
    if (link || error == ELOOP)
      throw Error("'" + path + "' is a symlink; it must be a directory of its own inside '" + parentPath +
                  "' (remove the link)");
    throw Error("cannot open '" + path + "': " + std::strerror(error) + " (it must be a directory)");
  }
  return dir;
}

UniqueFd createReplacing(int dir, const std::string& dirPath, const std::string& name) {
  const std::string path = join(dirPath, name);
  const auto fail = [&](const std::string& what, int error) {
    return Error("cannot " + what + " '" + path + "': " + std::strerror(error) +
                 (error == EEXIST ? " (the name was made again while it was being replaced: who else writes there?)"
                                  : " (check the output directory)"));
  };
  // Opened without following a symlink and without truncating, then looked at through the descriptor: a file
  // of one link (ours, from an earlier run) is truncated; a symlink or a file with other links (planted) is
  // unlinked and made anew; a device (e.g. /dev/full) is written as before, never removed.
  UniqueFd fd(::openat(dir, name.c_str(), O_WRONLY | O_NOFOLLOW | O_CLOEXEC));
  if (fd.valid()) {
    struct stat st {};
    if (::fstat(fd.get(), &st) != 0) throw fail("examine", errno);
    if (!S_ISREG(st.st_mode)) return fd;
    if (st.st_nlink == 1) {
      if (::ftruncate(fd.get(), 0) != 0) throw fail("truncate", errno);
      return fd;
    }
    fd.reset();
  } else if (errno != ENOENT && errno != ELOOP) {
    throw fail("open", errno);
  }
  if (::unlinkat(dir, name.c_str(), 0) != 0 && errno != ENOENT) throw fail("replace", errno);
  fd.reset(openExclusive(dir, name));
  if (!fd.valid()) throw fail("create", errno);
  return fd;
}

UniqueFd createReplacing(const std::string& path) {
  const auto [dirPath, name] = splitPath(path);
  const UniqueFd dir = openDirectory(dirPath);
  return createReplacing(dir.get(), dirPath, name);
}

TemporaryFile::TemporaryFile(const std::string& target, const std::string& tag) {
  std::tie(dirPath_, targetName_) = splitPath(target);
  try {
    dir_ = openDirectory(dirPath_);
  } catch (const Error& e) {
    throw Error("cannot write '" + target + "': " + e.what());
  }
  create(tag);
}

TemporaryFile::TemporaryFile(int dir, const std::string& dirPath, const std::string& targetName,
                             const std::string& tag)
    : dir_(::fcntl(dir, F_DUPFD_CLOEXEC, 0)), dirPath_(dirPath), targetName_(targetName) {
  if (!dir_.valid()) throw Error("cannot use the directory '" + dirPath + "': " + std::strerror(errno));
  create(tag);
}

void TemporaryFile::create(const std::string& tag) {
  for (int attempt = 0; attempt < kNameAttempts && !fd_.valid(); ++attempt) {
    name_ = targetName_ + tag + "." + randomSuffix();
    fd_.reset(openExclusive(dir_.get(), name_));
    if (!fd_.valid() && errno != EEXIST) break;
  }
  path_ = join(dirPath_, name_);
  if (!fd_.valid())
    throw Error("cannot create a temporary file for '" + join(dirPath_, targetName_) + "' in '" + dirPath_ +
                "': " + std::strerror(errno) + " (check that the directory exists and is writable)");
}

TemporaryFile::~TemporaryFile() {
  if (stream_) std::fclose(stream_);
  if (!committed_ && fd_.valid()) ::unlinkat(dir_.get(), name_.c_str(), 0);
}

std::FILE* TemporaryFile::stream() {
  if (stream_) return stream_;
  const int copy = ::fcntl(fd_.get(), F_DUPFD_CLOEXEC, 0);
  if (copy >= 0) stream_ = ::fdopen(copy, "w+b");
  if (!stream_) {
    const int error = errno;
    if (copy >= 0) ::close(copy);
    throw Error("cannot write '" + path_ + "': " + std::strerror(error));
  }
  return stream_;
}

void TemporaryFile::commit() {
  if (stream_) {
    errno = 0;
    const bool failed = std::fflush(stream_) != 0 || std::ferror(stream_);
    const int writeError = errno ? errno : EIO;
    const int closeError = std::fclose(stream_) != 0 ? errno : 0;
    stream_ = nullptr;
    if (failed || closeError) {
      const int error = failed ? writeError : closeError;
      throwWriteFailure("writing '" + path_ + "' failed: " + std::strerror(error),
                        join(dirPath_, targetName_), error);
    }
  }
  if (::renameat(dir_.get(), name_.c_str(), dir_.get(), targetName_.c_str()) != 0)
    throw Error("cannot rename '" + path_ + "' to '" + join(dirPath_, targetName_) + "': " + std::strerror(errno));
  committed_ = true;
}

}  // namespace sb
