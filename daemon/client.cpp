#include "daemon/client.h"

#include <sys/socket.h>

#include <cerrno>

namespace sb::daemon {

Client::Client(UniqueFd fd, PeerCredentials peer, size_t maxRequestBytes, size_t maxQueuedBytes)
    : fd_(std::move(fd)),
      peer_(std::move(peer)),
      maxRequestBytes_(maxRequestBytes),
      maxQueuedBytes_(maxQueuedBytes) {}

Client::ReadResult Client::read(const std::function<void(std::string_view)>& onLine,
                                const std::function<void()>& onOversize) {
  char buf[4096];
  // At most 64 KiB per call, so that one flooding client cannot starve the others (epoll calls again).
  for (int reads = 0; reads < 16; ++reads) {
    const ssize_t n = ::recv(fd_.get(), buf, sizeof buf, 0);
    if (n == 0) return ReadResult::closed;  // a half line left in input_ is discarded with the client
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno == EAGAIN || errno == EWOULDBLOCK) return ReadResult::open;
      return ReadResult::closed;
    }
    std::string_view chunk(buf, static_cast<size_t>(n));
    while (!chunk.empty()) {
      const size_t nl = chunk.find('\n');
      const std::string_view part = chunk.substr(0, nl);
      if (discarding_) {
        if (nl != std::string_view::npos) discarding_ = false;
      } else if (input_.size() + part.size() > maxRequestBytes_) {
        input_.clear();
        discarding_ = nl == std::string_view::npos;
        onOversize();
      } else {
        input_.append(part);
        if (nl != std::string_view::npos) {
          const std::string line = std::move(input_);
          input_.clear();
          onLine(line);
        }
      }
      if (nl == std::string_view::npos) break;
      chunk.remove_prefix(nl + 1);
    }
  }
  return ReadResult::open;
}

bool Client::send(Line line) {
  if (queuedBytes_ + line->size() > maxQueuedBytes_) {
    ++dropped_;
    if (!stalledSince_) stalledSince_ = SteadyClock::now();
    return false;
  }
  queuedBytes_ += line->size();
  queue_.push_back(std::move(line));
  return true;
}

bool Client::flush() {
  bool progressed = false;
  while (!queue_.empty()) {
    const std::string& head = *queue_.front();
    const ssize_t n = ::send(fd_.get(), head.data() + headOffset_, head.size() - headOffset_, MSG_NOSIGNAL);
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno == EAGAIN || errno == EWOULDBLOCK) break;
      return false;
    }
    progressed = progressed || n > 0;
    headOffset_ += static_cast<size_t>(n);
    if (headOffset_ == head.size()) {
      queuedBytes_ -= head.size();
      queue_.pop_front();
      headOffset_ = 0;
    }
  }
  // Draining anything ends a stall: the client reads, just slowly.
  if (progressed) stalledSince_.reset();
  return true;
}

}  // namespace sb::daemon
