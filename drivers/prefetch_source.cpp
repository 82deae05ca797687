#include "drivers/prefetch_source.h"

#include "core/error.h"

namespace sb {

PrefetchSource::PrefetchSource(std::unique_ptr<FrameSource> source, size_t depth, size_t threads)
    : info_(source ? source->info() : SequenceInfo{}), source_(std::move(source)), depth_(depth) {
  if (!source_) throw Error("PrefetchSource needs a frame source");
  if (depth_ == 0) throw Error("prefetch depth must be at least 1 frame");
  if (threads == 0) throw Error("prefetching needs at least 1 thread");
  randomAccess_ = dynamic_cast<const RandomAccessSource*>(source_.get());
  if (randomAccess_) {
    count_ = randomAccess_->count();
  } else {
    threads = 1;  // next() is sequential
  }
  for (size_t t = 0; t < threads; ++t) workers_.emplace_back([this] { run(); });
}

PrefetchSource::~PrefetchSource() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  space_.notify_all();
  for (std::thread& w : workers_) w.join();
}

void PrefetchSource::run() {
  for (;;) {
    size_t index = 0;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      space_.wait(lock,
                  [this] { return stop_ || failed_ || claimed_ >= count_ || claimed_ < consumed_ + depth_; });
      if (stop_ || failed_ || claimed_ >= count_) return;
      index = claimed_++;
      window_.emplace_back();
    }
    Slot result;
    result.done = true;
    try {
      result.frame = randomAccess_ ? randomAccess_->load(index) : source_->next();
    } catch (...) {
      result.error = std::current_exception();
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!result.frame && !result.error) {  // the sequential source ended: `index` does not exist
        count_ = index;
        window_.pop_back();
      } else {
        if (result.error) failed_ = true;
        window_[index - consumed_] = std::move(result);
      }
    }
    ready_.notify_all();
    space_.notify_all();  // other workers re-check failed_ / count_
  }
}

std::optional<DepthFrame> PrefetchSource::next() {
  std::unique_lock<std::mutex> lock(mutex_);
  if (error_) std::rethrow_exception(error_);
  ready_.wait(lock, [this] { return consumed_ >= count_ || (!window_.empty() && window_.front().done); });
  if (consumed_ >= count_) return std::nullopt;
  Slot slot = std::move(window_.front());
  window_.pop_front();
  ++consumed_;
  if (slot.error) {
    error_ = slot.error;
    std::rethrow_exception(error_);
  }
  lock.unlock();
  space_.notify_all();
  return std::move(slot.frame);
}

}  // namespace sb
