#pragma once
// Decodes ahead: wraps any FrameSource and calls its next() on a worker thread, keeping up to `depth` frames
// in a bounded queue. Frames come out in the wrapped source's order; an exception the wrapped source throws
// reaches the caller of next() at the position where it happened (after every frame decoded before it), and
// again on every later call. Destroying a PrefetchSource mid-sequence stops the worker after the frame it is
// decoding and joins it.

#include <condition_variable>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "drivers/frame_source.h"

namespace sb {

class PrefetchSource : public FrameSource {
 public:
  // `depth` >= 1: frames decoded ahead of the caller.
  PrefetchSource(std::unique_ptr<FrameSource> source, size_t depth);
  ~PrefetchSource() override;
  PrefetchSource(const PrefetchSource&) = delete;
  PrefetchSource& operator=(const PrefetchSource&) = delete;

  const SequenceInfo& info() const override { return info_; }
  std::optional<DepthFrame> next() override;

 private:
  void run();

  const SequenceInfo info_;  // copied at construction: the worker owns the wrapped source afterwards
  std::unique_ptr<FrameSource> source_;
  const size_t depth_;

  std::mutex mutex_;
  std::condition_variable ready_;  // a frame, the end or an error is available
  std::condition_variable space_;  // the queue has room, or stop was requested
  std::deque<DepthFrame> queue_;
  bool ended_ = false;             // the worker has seen the end or an error (after the queued frames)
  std::exception_ptr error_;       // the wrapped source's exception, delivered after the queued frames
  bool stop_ = false;

  std::thread worker_;  // last: started after every other member exists
};

}  // namespace sb
