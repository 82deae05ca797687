#include "daemon/capture_thread.h"

#include <spdlog/spdlog.h>

#include "core/input_file.h"

namespace sb::daemon {

void CaptureThread::start(CaptureSource& source, FrameQueue& queue) {
  thread_ = std::thread([this, &source, &queue] {
    try {
      while (auto frame = source.next())
        if (!queue.push(std::move(*frame))) break;
    } catch (const std::exception& e) {
      spdlog::error("source: {}", sb::printable(e.what()));
      {
        std::lock_guard lock(mutex_);
        error_ = e.what();
      }
      queue.close(std::string("the input failed: ") + e.what());  // the pass is reported failed
      return;
    }
    queue.close();
  });
}

void CaptureThread::join() {
  if (thread_.joinable()) thread_.join();
}

std::string CaptureThread::error() const {
  std::lock_guard lock(mutex_);
  return error_;
}

}  // namespace sb::daemon
