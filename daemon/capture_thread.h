#pragma once
// The capture thread (architecture.md, "One frame"): it takes frames from the source and pushes them into the
// queue until the source ends (the queue is closed after its frames) or fails (the queue is closed with the
// error, so the SLAM thread reports the pass failed). It owns nothing but its thread and the error.

#include <mutex>
#include <string>
#include <thread>

#include "daemon/capture_source.h"
#include "daemon/frame_queue.h"

namespace sb::daemon {

class CaptureThread {
 public:
  CaptureThread() = default;
  CaptureThread(const CaptureThread&) = delete;
  CaptureThread& operator=(const CaptureThread&) = delete;
  ~CaptureThread() { join(); }

  // Starts the thread; `source` and `queue` must outlive it (join() before they go).
  void start(CaptureSource& source, FrameQueue& queue);
  void join();
  // Why the input failed; empty while it has not. Any thread.
  std::string error() const;

 private:
  std::thread thread_;
  mutable std::mutex mutex_;
  std::string error_;
};

}  // namespace sb::daemon
