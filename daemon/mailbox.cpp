#include "daemon/mailbox.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "core/error.h"

namespace sb::daemon {

Mailbox::Mailbox(EventLoop& loop, size_t capacity)
    : loop_(loop), capacity_(capacity), event_(eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC)) {
  if (!event_.valid()) throw Error(std::string("eventfd failed: ") + std::strerror(errno));
  loop_.add(event_.get(), EPOLLIN, [this](uint32_t) { drain(); });
}

Mailbox::~Mailbox() {
  loop_.remove(event_.get());
}

void Mailbox::post(std::function<void()> work) {
  {
    std::lock_guard lock(mutex_);
    if (items_.size() >= capacity_) {
      items_.pop_front();
      ++dropped_;
    }
    items_.push_back(std::move(work));
  }
  const uint64_t one = 1;
  (void)!::write(event_.get(), &one, sizeof one);  // EAGAIN only when the counter is saturated: still woken
}

uint64_t Mailbox::dropped() const {
  std::lock_guard lock(mutex_);
  return dropped_;
}

void Mailbox::drain() {
  uint64_t count = 0;
  (void)!::read(event_.get(), &count, sizeof count);
  std::deque<std::function<void()>> items;
  {
    std::lock_guard lock(mutex_);
    items.swap(items_);
  }
  for (auto& work : items) work();
}

}  // namespace sb::daemon
