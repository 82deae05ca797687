#include "core/thread_pool.h"

#include <memory>

namespace sb {

namespace {
unsigned g_globalThreads = 0;
}

ThreadPool::ThreadPool(unsigned threads) {
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  for (unsigned i = 1; i < threads; ++i) workers_.emplace_back([this] { workerLoop(); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (auto& w : workers_) w.join();
}

void ThreadPool::runChunks() {
  for (;;) {
    const int c = next_.fetch_add(1);
    if (c >= chunks_) break;
    const int b = begin_ + c * chunk_;
    const int e = std::min(end_, b + chunk_);
    try {
      (*job_)(c, b, e);
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
    }
  }
}

void ThreadPool::workerLoop() {
  unsigned seen = 0;
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      ++active_;
    }
    runChunks();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (--active_ == 0) done_.notify_all();
    }
  }
}

void ThreadPool::parallelFor(int begin, int end, int chunk, const std::function<void(int, int, int)>& fn) {
  if (chunk < 1) chunk = 1;
  const int chunks = chunkCount(begin, end, chunk);
  if (chunks == 0) return;
  if (chunks == 1 || workers_.empty()) {
    for (int c = 0; c < chunks; ++c) fn(c, begin + c * chunk, std::min(end, begin + (c + 1) * chunk));
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = &fn;
    begin_ = begin;
    end_ = end;
    chunk_ = chunk;
    chunks_ = chunks;
    next_ = 0;
    error_ = nullptr;
    ++generation_;
  }
  wake_.notify_all();
  runChunks();
  std::exception_ptr err;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [&] { return active_ == 0 && next_ >= chunks_; });
    job_ = nullptr;
    err = error_;
    error_ = nullptr;
  }
  if (err) std::rethrow_exception(err);
}

ThreadPool& ThreadPool::global() {
  static ThreadPool pool(g_globalThreads);
  return pool;
}

void ThreadPool::setGlobalThreads(unsigned threads) { g_globalThreads = threads; }

}  // namespace sb
