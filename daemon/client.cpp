#include "daemon/client.h"

#include <sys/socket.h>

#include <cerrno>

namespace sb::daemon {

Client::Client(UniqueFd fd, PeerCredentials peer, size_t maxRequestBytes, size_t maxQueuedBytes)
    : fd_(std::move(fd)),
      peer_(std::move(peer)),
      maxRequestBytes_(maxRequestBytes),
      maxQueuedBytes_(maxQueuedBytes) {}

Client::ReadResult Client::read() {
  char buf[4096];
  // One recv holds up to ~450 short requests: the loop ends as soon as enough lines wait (served over the
  // next event-loop turns within the per-client and per-uid budgets of the server).
  for (int reads = 0; reads < 16 && wantsInput(); ++reads) {
    const ssize_t n = ::recv(fd_.get(), buf, sizeof buf, 0);
    if (n == 0) {  // a half line left in input_ is discarded with the client
      peerClosed_ = true;
      break;
    }
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno == EAGAIN || errno == EWOULDBLOCK) break;
      return ReadResult::closed;
    }
    std::string_view chunk(buf, static_cast<size_t>(n));
    while (!chunk.empty()) {
      const size_t nl = chunk.find('\n');
      std::string_view part = chunk.substr(0, nl);
      // A '\r' ending the line ("\r\n") is not part of the request: it does not count against the cap. One
      // at the end of a chunk may be followed by the '\n' in the next one.
      const char last = !part.empty() ? part.back() : (input_.empty() ? '\0' : input_.back());
      const size_t counted = input_.size() + part.size() - (last == '\r' ? 1 : 0);
      if (discarding_) {
        if (nl != std::string_view::npos) discarding_ = false;
      } else if (counted > maxRequestBytes_) {
        input_.clear();
        discarding_ = nl == std::string_view::npos;
        lines_.push_back(PendingLine{std::string(), true});
      } else {
        input_.append(part);
        if (nl != std::string_view::npos) {
          if (!input_.empty() && input_.back() == '\r') input_.pop_back();
          lines_.push_back(PendingLine{std::move(input_), false});
          input_.clear();
        }
      }
      if (nl == std::string_view::npos) break;
      chunk.remove_prefix(nl + 1);
    }
  }
  return peerClosed_ && lines_.empty() ? ReadResult::closed : ReadResult::open;
}

Client::PendingLine Client::takeLine() {
  PendingLine line = std::move(lines_.front());
  lines_.pop_front();
  return line;
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
