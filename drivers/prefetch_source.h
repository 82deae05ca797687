#pragma once
// Decodes ahead: wraps any FrameSource and reads it on worker threads into a bounded window of `depth`
// frames. A RandomAccessSource (a TUM-layout sequence) is decoded by `threads` workers at once; any other
// source by one worker calling next(). Either way:
//  - frames come out in the wrapped source's order;
//  - an exception of the wrapped source reaches the caller of next() at the frame where it happened (after
//    every frame before it), and again on every later call: the source is finished after an error;
//  - destroying a PrefetchSource mid-sequence stops the workers after the frames they are decoding.

#include <condition_variable>
#include <deque>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "drivers/frame_source.h"
#include "drivers/random_access_source.h"

namespace sb {

class PrefetchSource : public FrameSource {
 public:
  // `depth` >= 1: frames decoded ahead of the caller. `threads` >= 1: decoding workers (only a
  // RandomAccessSource uses more than one).
  PrefetchSource(std::unique_ptr<FrameSource> source, size_t depth, size_t threads = 1);
  ~PrefetchSource() override;
  PrefetchSource(const PrefetchSource&) = delete;
  PrefetchSource& operator=(const PrefetchSource&) = delete;

  const SequenceInfo& info() const override { return info_; }
  std::optional<DepthFrame> next() override;

 private:
  static constexpr size_t kUnknown = std::numeric_limits<size_t>::max();

  struct Slot {
    bool done = false;
    std::optional<DepthFrame> frame;
    std::exception_ptr error;
  };

  void run();

  const SequenceInfo info_;  // copied at construction: the workers own the wrapped source afterwards
  std::unique_ptr<FrameSource> source_;
  const RandomAccessSource* randomAccess_ = nullptr;  // source_ when it supports concurrent decoding
  const size_t depth_;

  std::mutex mutex_;
  std::condition_variable ready_;  // the front slot is done, or the end is known
  std::condition_variable space_;  // the window has room, or stop was requested
  std::deque<Slot> window_;        // window_[k] holds frame consumed_ + k
  size_t consumed_ = 0;            // frames handed to the caller
  size_t claimed_ = 0;             // frames given to workers
  size_t count_ = kUnknown;        // total frames, once known
  bool failed_ = false;            // a worker hit an error: claim nothing more
  std::exception_ptr error_;       // delivered to the caller, rethrown on every later call
  bool stop_ = false;

  std::vector<std::thread> workers_;  // last: started after every other member exists
};

}  // namespace sb
