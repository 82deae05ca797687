#include "drivers/prefetch_source.h"

#include "core/error.h"

namespace sb {

PrefetchSource::PrefetchSource(std::unique_ptr<FrameSource> source, size_t depth)
    : info_(source ? source->info() : SequenceInfo{}), source_(std::move(source)), depth_(depth) {
  if (!source_) throw Error("PrefetchSource needs a frame source");
  if (depth_ == 0) throw Error("prefetch depth must be at least 1 frame");
  worker_ = std::thread([this] { run(); });
}

PrefetchSource::~PrefetchSource() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  space_.notify_all();
  worker_.join();
}

void PrefetchSource::run() {
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      space_.wait(lock, [this] { return stop_ || queue_.size() < depth_; });
      if (stop_) return;
    }
    std::optional<DepthFrame> frame;
    std::exception_ptr error;
    try {
      frame = source_->next();
    } catch (...) {
      error = std::current_exception();
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (frame) {
        queue_.push_back(std::move(*frame));
      } else {
        ended_ = true;
        error_ = error;
      }
    }
    ready_.notify_one();
    if (!frame) return;
  }
}

std::optional<DepthFrame> PrefetchSource::next() {
  std::unique_lock<std::mutex> lock(mutex_);
  ready_.wait(lock, [this] { return !queue_.empty() || ended_; });
  if (queue_.empty()) {
    if (error_) std::rethrow_exception(error_);
    return std::nullopt;
  }
  DepthFrame frame = std::move(queue_.front());
  queue_.pop_front();
  lock.unlock();
  space_.notify_one();
  return frame;
}

}  // namespace sb
