#pragma once
// The address of a Unix-domain socket at `path`, shared by the daemon's listening side and the client
// library's connecting side. Throws sb::Error when the path does not fit sockaddr_un.

#include <sys/socket.h>
#include <sys/un.h>

#include <cstring>
#include <string>

#include "core/error.h"

namespace sb {

inline sockaddr_un unixSocketAddress(const std::string& path) {
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (path.size() >= sizeof addr.sun_path)
    throw Error("socket path '" + path + "' is longer than " + std::to_string(sizeof addr.sun_path - 1) +
                " bytes");
  std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
  return addr;
}

}  // namespace sb
