#include "client/frame_pusher.h"

#include <poll.h>
#include <sys/socket.h>

#include <cerrno>
#include <cstring>

#include "client/connection.h"
#include "core/error.h"

namespace sb::client {

FramePusher::FramePusher(const std::string& socketPath) : path_(socketPath), fd_(connectUnix(socketPath)) {}

void FramePusher::writeAll(const uint8_t* data, size_t bytes) {
  size_t off = 0;
  while (off < bytes) {
    const ssize_t n = ::send(fd_.get(), data + off, bytes - off, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      throw Error("cannot push a frame to '" + path_ + "': " + std::strerror(errno) +
                  " (did slamboosterd stop or restart?)");
    off += static_cast<size_t>(n);
  }
}

bool FramePusher::closedByDaemon() const {
  pollfd p{fd_.get(), POLLRDHUP, 0};
  return ::poll(&p, 1, 0) == 1 && (p.revents & (POLLRDHUP | POLLHUP | POLLERR));
}

void FramePusher::push(PushedFrameHeader header, const DepthRaw& depth) {
  // The daemon closes a pusher silent for source.push_timeout_s: a pusher that paused (a camera that stopped
  // for a while) connects again before the frame instead of losing it to a closed connection.
  if (closedByDaemon()) fd_ = connectUnix(path_);
  header.width = static_cast<uint32_t>(depth.width());
  header.height = static_cast<uint32_t>(depth.height());
  const auto head = encodePushedHeader(header);
  writeAll(head.data(), head.size());
  writeAll(reinterpret_cast<const uint8_t*>(depth.data()), depth.size() * sizeof(uint16_t));
}

}  // namespace sb::client
