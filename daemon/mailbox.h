#pragma once
// Hands work from any thread (the SLAM thread, the capture thread) to the event-loop thread without ever
// blocking the sender: a bounded queue of closures plus an eventfd that wakes the loop. When the loop falls
// behind by `capacity` items, the oldest is dropped and counted (it never should: the loop does not block).

#include <sys/eventfd.h>

#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>

#include "daemon/event_loop.h"
#include "core/unique_fd.h"

namespace sb::daemon {

class Mailbox {
 public:
  Mailbox(EventLoop& loop, size_t capacity);
  ~Mailbox();
  Mailbox(const Mailbox&) = delete;
  Mailbox& operator=(const Mailbox&) = delete;

  // Any thread. Never blocks (beyond a short lock).
  void post(std::function<void()> work);
  uint64_t dropped() const;

 private:
  void drain();  // on the loop thread

  EventLoop& loop_;
  const size_t capacity_;
  UniqueFd event_;
  mutable std::mutex mutex_;
  std::deque<std::function<void()>> items_;
  uint64_t dropped_ = 0;
};

}  // namespace sb::daemon
