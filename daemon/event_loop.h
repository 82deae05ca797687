#pragma once
// A small epoll loop: file descriptors with handlers, run on one thread (the daemon's event-loop thread,
// which owns the sockets). Handlers may add and remove descriptors, including their own, at any time.

#include <sys/epoll.h>

#include <cstdint>
#include <functional>
#include <unordered_map>

#include "core/unique_fd.h"

namespace sb::daemon {

class EventLoop {
 public:
  using Handler = std::function<void(uint32_t events)>;  // EPOLLIN, EPOLLOUT, EPOLLHUP, EPOLLERR bits

  EventLoop();  // throws sb::Error when epoll is unavailable
  EventLoop(const EventLoop&) = delete;
  EventLoop& operator=(const EventLoop&) = delete;

  // Watches `fd` (borrowed: the caller closes it after remove()) for `events`.
  void add(int fd, uint32_t events, Handler handler);
  void modify(int fd, uint32_t events);
  void remove(int fd);

  // Called after each turn (one batch of events); while it returns true (work is left) the next turn does
  // not wait for events. nullptr: none.
  void setAfterTurn(std::function<bool()> afterTurn) { afterTurn_ = std::move(afterTurn); }

  // Dispatches events until stop() is called (from a handler).
  void run();
  void stop() { running_ = false; }

 private:
  struct Entry {
    uint64_t id;
    Handler handler;
  };
  UniqueFd epoll_;
  std::unordered_map<int, Entry> entries_;    // by fd
  std::unordered_map<uint64_t, int> fdById_;  // ids in flight: a removed entry's events are ignored
  uint64_t nextId_ = 1;
  bool running_ = false;
  std::function<bool()> afterTurn_;
};

}  // namespace sb::daemon
