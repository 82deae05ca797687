#pragma once
// The bounded hand-over between the capture thread and the SLAM thread. Two policies:
//  - wait (replay): push() waits for room, so no frame is ever lost;
//  - newest (live): push() never waits; when the queue is full the oldest frame is dropped and counted, so
//    the SLAM thread always gets the newest frames.
// close() ends the stream after the queued frames; abort() ends it at once, discarding them. close(error)
// ends it after the queued frames because the input failed: the SLAM thread reports the pass as failed.

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>

#include "daemon/capture_source.h"

namespace sb::daemon {

class FrameQueue {
 public:
  enum class Policy { wait, newest };
  FrameQueue(size_t capacity, Policy policy) : capacity_(capacity < 1 ? 1 : capacity), policy_(policy) {}

  // False when the queue was closed or aborted (the frame is discarded).
  bool push(CapturedFrame frame) {
    std::unique_lock lock(mutex_);
    if (policy_ == Policy::wait) space_.wait(lock, [&] { return items_.size() < capacity_ || closed_; });
    if (closed_) return false;
    if (items_.size() >= capacity_) {
      items_.pop_front();
      ++dropped_;
    }
    items_.push_back(std::move(frame));
    ready_.notify_one();
    return true;
  }

  // The next frame; nullopt once closed and drained, or aborted.
  std::optional<CapturedFrame> pop() {
    std::unique_lock lock(mutex_);
    ready_.wait(lock, [&] { return !items_.empty() || closed_; });
    if (items_.empty()) return std::nullopt;
    CapturedFrame f = std::move(items_.front());
    items_.pop_front();
    space_.notify_one();
    return f;
  }

  // `error`: why the input ended early (empty: it ended normally).
  void close(const std::string& error = {}) {
    std::lock_guard lock(mutex_);
    closed_ = true;
    if (error_.empty()) error_ = error;
    ready_.notify_all();
    space_.notify_all();
  }
  void abort() {
    std::lock_guard lock(mutex_);
    closed_ = true;
    items_.clear();
    ready_.notify_all();
    space_.notify_all();
  }

  uint64_t dropped() const {
    std::lock_guard lock(mutex_);
    return dropped_;
  }
  // Why the input ended early (close(error)); empty while it runs or when it ended normally.
  std::string error() const {
    std::lock_guard lock(mutex_);
    return error_;
  }
  size_t size() const {
    std::lock_guard lock(mutex_);
    return items_.size();
  }

 private:
  const size_t capacity_;
  const Policy policy_;
  mutable std::mutex mutex_;
  std::condition_variable ready_, space_;
  std::deque<CapturedFrame> items_;
  uint64_t dropped_ = 0;
  bool closed_ = false;
  std::string error_;
};

}  // namespace sb::daemon
