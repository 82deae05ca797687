#include "core/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/error.h"

namespace sb {

namespace {

// Bytes read from the file per refill of an InputFile's buffer.
constexpr size_t kInputBufferBytes = 65536;

// What a non-regular file is, from its mode; empty for a regular file.
std::string kindProblem(mode_t mode) {
  if (S_ISREG(mode)) return "";
  if (S_ISDIR(mode)) return "is a directory";
  if (S_ISFIFO(mode)) return "is a named pipe (FIFO), not a file";
  if (S_ISSOCK(mode)) return "is a socket, not a file";
  if (S_ISCHR(mode)) return "is a character device, not a file";
  if (S_ISBLK(mode)) return "is a block device, not a file";
  return "is not a regular file";
}

// What a failed stat() or open() of `path` with `error` (errno) means.
std::string errnoProblem(const std::string& path, int error) {
  switch (error) {
    case ENOENT: {
      struct stat link {};
      if (::lstat(path.c_str(), &link) == 0 && S_ISLNK(link.st_mode))
        return "is a symbolic link to something that does not exist";
      return "does not exist";
    }
    case ENOTDIR: return "does not exist (a part of its path is not a directory)";
    case ELOOP: return "is a symbolic-link loop (too many levels of symbolic links)";
    case EACCES:
      return "cannot be read: permission denied (the file, or a directory on its path, is not readable by this "
             "user)";
    case ENAMETOOLONG: return "is a name too long for the system";
    default: return std::string("cannot be read: ") + std::strerror(error);
  }
}

class FdStreamBuf : public std::streambuf {
 public:
  explicit FdStreamBuf(UniqueFd fd) : fd_(std::move(fd)), buffer_(new char[kInputBufferBytes]) {}

 protected:
  int_type underflow() override {
    if (gptr() < egptr()) return traits_type::to_int_type(*gptr());
    ssize_t n;
    do {
      n = ::read(fd_.get(), buffer_.get(), kInputBufferBytes);
    } while (n < 0 && errno == EINTR);
    if (n < 0) throw Error(std::string("reading failed: ") + std::strerror(errno));  // istream sets badbit
    if (n == 0) return traits_type::eof();
    setg(buffer_.get(), buffer_.get(), buffer_.get() + n);
    return traits_type::to_int_type(*gptr());
  }

 private:
  UniqueFd fd_;
  std::unique_ptr<char[]> buffer_;
};

}  // namespace

std::string pathProblem(const std::string& path) {
  if (path.empty()) return "is empty (no path given)";
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return errnoProblem(path, errno);
  if (!S_ISREG(st.st_mode)) return kindProblem(st.st_mode);
  UniqueFd fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY));
  if (!fd.valid()) return errnoProblem(path, errno);
  return "";
}

bool isReadableRegularFile(const std::string& path) { return pathProblem(path).empty(); }

UniqueFd openRegularFile(const std::string& path, const std::string& what) {
  const auto fail = [&](const std::string& problem) {
    return Error("cannot open " + what + " " + quoteForMessage(path) + ": it " + problem +
                 " (give the path of a readable regular file)");
  };
  // stat first: a device is never opened (opening one can have effects), a FIFO's open would block.
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw fail(errnoProblem(path, errno));
  if (!S_ISREG(st.st_mode)) throw fail(kindProblem(st.st_mode));
  // O_NONBLOCK: should the path have become a FIFO since, open() still returns at once; fstat then refuses it.
  UniqueFd fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY));
  if (!fd.valid()) throw fail(errnoProblem(path, errno));
  if (::fstat(fd.get(), &st) != 0) throw fail(std::string("cannot be read: ") + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw fail(kindProblem(st.st_mode));
  const int flags = ::fcntl(fd.get(), F_GETFL);
  if (flags >= 0) ::fcntl(fd.get(), F_SETFL, flags & ~O_NONBLOCK);
  return fd;
}

InputFile::InputFile(const std::string& path, const std::string& what)
    : std::istream(nullptr), buffer_(std::make_unique<FdStreamBuf>(openRegularFile(path, what))) {
  rdbuf(buffer_.get());
}

InputFile::~InputFile() = default;

std::string printable(std::string_view text, size_t maxBytes) {
  static const char* const kHex = "0123456789abcdef";
  std::string out;
  const auto append = [&](std::string_view part) {
    for (const char c : part) {
      const auto u = static_cast<unsigned char>(c);
      if ((u < 0x20 && c != '\n' && c != '\t') || u == 0x7f) {
        out += "\\x";
        out += kHex[u >> 4];
        out += kHex[u & 15];
      } else {
        out += c;
      }
    }
  };
  if (text.size() <= maxBytes) {
    append(text);
  } else {
    const size_t head = maxBytes / 2, tail = maxBytes / 4;
    append(text.substr(0, head));
    out += " [... " + std::to_string(text.size() - head - tail) + " bytes cut ...] ";
    append(text.substr(text.size() - tail));
  }
  return out;
}

std::string quoteForMessage(std::string_view value, size_t maxBytes) {
  std::string out = "'" + printable(value, maxBytes) + "'";
  for (size_t i = 1; i + 1 < out.size(); ++i)  // one line: a newline in a name is escaped too
    if (out[i] == '\n') out.replace(i, 1, "\\x0a");
  return out;
}

}  // namespace sb
