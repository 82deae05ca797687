#include "daemon/event_loop.h"

#include <cerrno>
#include <cstring>
#include <string>

#include "core/error.h"

namespace sb::daemon {

EventLoop::EventLoop() : epoll_(epoll_create1(EPOLL_CLOEXEC)) {
  if (!epoll_.valid()) throw Error(std::string("epoll_create1 failed: ") + std::strerror(errno));
}

void EventLoop::add(int fd, uint32_t events, Handler handler) {
  const uint64_t id = nextId_++;
  epoll_event ev{};
  ev.events = events;
  ev.data.u64 = id;
  if (epoll_ctl(epoll_.get(), EPOLL_CTL_ADD, fd, &ev) != 0)
    throw Error("epoll_ctl(ADD, fd " + std::to_string(fd) + ") failed: " + std::strerror(errno));
  entries_[fd] = Entry{id, std::move(handler)};
  fdById_[id] = fd;
}

void EventLoop::modify(int fd, uint32_t events) {
  auto it = entries_.find(fd);
  if (it == entries_.end()) return;
  epoll_event ev{};
  ev.events = events;
  ev.data.u64 = it->second.id;
  epoll_ctl(epoll_.get(), EPOLL_CTL_MOD, fd, &ev);
}

void EventLoop::remove(int fd) {
  auto it = entries_.find(fd);
  if (it == entries_.end()) return;
  epoll_ctl(epoll_.get(), EPOLL_CTL_DEL, fd, nullptr);
  fdById_.erase(it->second.id);
  entries_.erase(it);
}

void EventLoop::run() {
  running_ = true;
  epoll_event events[64];
  bool workLeft = false;
  while (running_) {
    const int n = epoll_wait(epoll_.get(), events, 64, workLeft ? 0 : -1);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw Error(std::string("epoll_wait failed: ") + std::strerror(errno));
    }
    for (int i = 0; i < n && running_; ++i) {
      auto id = fdById_.find(events[i].data.u64);
      if (id == fdById_.end()) continue;  // removed by an earlier handler of this batch
      // Copy: the handler may remove (and destroy) its own entry.
      Handler handler = entries_.at(id->second).handler;
      handler(events[i].events);
    }
    workLeft = running_ && afterTurn_ && afterTurn_();
  }
}

}  // namespace sb::daemon
