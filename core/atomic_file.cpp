#include "core/atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "core/error.h"

namespace sb {

std::string temporaryPathFor(const std::string& path) { return path + ".tmp"; }

void writeFileAtomically(const std::string& path, const std::function<void(const std::string&)>& write) {
  const std::string temporary = temporaryPathFor(path);
  try {
    write(temporary);
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const int error = errno;
    std::remove(temporary.c_str());
    throw Error("cannot rename '" + temporary + "' to '" + path + "': " + std::strerror(error));
  }
}

}  // namespace sb
