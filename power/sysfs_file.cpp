#include "power/sysfs_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "core/error.h"
#include "core/unique_fd.h"

namespace sb::power {

namespace {

std::string failure(const std::string& path, const char* what, int errnum) {
  std::string message = "cannot " + std::string(what) + " '" + path + "': " + std::strerror(errnum);
  if (errnum == EACCES || errnum == EPERM)
    message += " (run as root, or give the service's user access with a udev rule or tmpfiles.d entry)";
  return message;
}

std::string readToken(const std::string& path) {
  UniqueFd fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));  // a FIFO never blocks
  if (!fd.valid()) throw Error(failure(path, "open", errno));
  char buffer[64];
  ssize_t n;
  do {
    n = ::read(fd.get(), buffer, sizeof buffer - 1);
  } while (n < 0 && errno == EINTR);
  if (n < 0) throw Error(failure(path, "read", errno));
  buffer[n] = '\0';
  std::string token(buffer);
  const size_t end = token.find_first_of(" \t\r\n");
  if (end != std::string::npos) token.resize(end);
  if (token.empty()) throw Error("'" + path + "' is empty (expected a number)");
  return token;
}

}  // namespace

double readSysfsNumber(const std::string& path) {
  const std::string token = readToken(path);
  char* end = nullptr;
  const double value = std::strtod(token.c_str(), &end);
  if (end == token.c_str() || *end != '\0') throw Error("'" + path + "' holds '" + token + "', not a number");
  return value;
}

unsigned long long readSysfsCounter(const std::string& path) {
  const std::string token = readToken(path);
  char* end = nullptr;
  errno = 0;
  const unsigned long long value = std::strtoull(token.c_str(), &end, 10);
  if (end == token.c_str() || *end != '\0' || errno != 0 || token[0] == '-')
    throw Error("'" + path + "' holds '" + token + "', not an unsigned counter");
  return value;
}

void writeSysfs(const std::string& path, const std::string& value) {
  UniqueFd fd(::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC));  // a FIFO never blocks
  if (!fd.valid()) throw Error(failure(path, "open for writing", errno));
  if (::write(fd.get(), value.data(), value.size()) != static_cast<ssize_t>(value.size()))
    throw Error(failure(path, "write", errno));
}

}  // namespace sb::power
