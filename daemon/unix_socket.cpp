#include "daemon/unix_socket.h"

#include <fcntl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <systemd/sd-daemon.h>

#include <cerrno>
#include <cstring>

#include "core/error.h"
#include "core/unix_address.h"

namespace sb::daemon {

namespace {

bool someoneListens(const std::string& path) {
  UniqueFd probe(socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
  const sockaddr_un addr = unixSocketAddress(path);
  return probe.valid() && connect(probe.get(), reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0;
}

}  // namespace

ListeningSocket::~ListeningSocket() {
  if (fd.valid() && !activated && !path.empty()) ::unlink(path.c_str());
}

ListeningSocket openListeningSocket(const std::string& path, unsigned mode) {
  ListeningSocket s;
  const int passed = sd_listen_fds(1);  // unsets LISTEN_FDS so children do not inherit it
  if (passed < 0)
    throw Error(std::string("socket activation: sd_listen_fds failed: ") + std::strerror(-passed));
  if (passed > 1)
    throw Error("socket activation: systemd passed " + std::to_string(passed) +
                " sockets; the .socket unit must have exactly one ListenStream=");
  if (passed == 1) {
    const int fd = SD_LISTEN_FDS_START;
    if (sd_is_socket_unix(fd, SOCK_STREAM, 1, nullptr, 0) <= 0)
      throw Error(
          "socket activation: the passed socket is not a listening Unix stream socket (ListenStream=PATH)");
    s.fd.reset(fd);
    s.activated = true;
    sockaddr_un addr{};
    socklen_t len = sizeof addr;
    if (getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) == 0) s.path = addr.sun_path;
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
    fcntl(fd, F_SETFD, FD_CLOEXEC);
    return s;
  }
  return bindListeningSocket(path, mode);
}

ListeningSocket bindListeningSocket(const std::string& path, unsigned mode, const std::string& key) {
  ListeningSocket s;
  const sockaddr_un addr = unixSocketAddress(path);
  struct stat st {};
  if (lstat(path.c_str(), &st) == 0) {
    if (!S_ISSOCK(st.st_mode))
      throw Error("socket path '" + path + "' exists and is not a socket; remove it or set " + key);
    if (someoneListens(path))
      throw Error("socket '" + path + "' is in use by another process (is slamboosterd already running?)");
    ::unlink(path.c_str());  // stale, from a daemon that did not exit cleanly
  }
  s.fd.reset(socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
  if (!s.fd.valid()) throw Error(std::string("socket(AF_UNIX) failed: ") + std::strerror(errno));
  // Created with no permissions for others, then opened up to `mode`: no window where it is too open.
  const mode_t old = umask(0777 & ~mode);
  const int bound = bind(s.fd.get(), reinterpret_cast<const sockaddr*>(&addr), sizeof addr);
  const int bindErrno = errno;
  umask(old);
  if (bound != 0)
    throw Error("cannot create socket '" + path + "': " + std::strerror(bindErrno) +
                " (does the directory exist and is it writable? set " + key + ")");
  s.path = path;
  if (chmod(path.c_str(), mode) != 0)
    throw Error("cannot set mode of socket '" + path + "': " + std::strerror(errno));
  if (listen(s.fd.get(), 128) != 0) throw Error("listen on '" + path + "' failed: " + std::strerror(errno));
  return s;
}

}  // namespace sb::daemon
