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

void ThreadPool::runChunks(const Job& job) {
  for (;;) {
    const int c = next_.fetch_add(1);
    if (c >= job.chunks) break;
    const int b = job.begin + c * job.chunk;
    const int e = std::min(job.end, b + job.chunk);
    try {
      (*job.fn)(c, b, e);
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
    }
  }
}

// A worker joins a generation only while its job is still posted: it registers (active_) and copies the job
// under the lock, runs chunks until none are left, and checks out. parallelFor retires the job, under the
// lock, once every chunk is taken and no registered worker is still running one; a worker that wakes after
// that finds no job and goes back to sleep. So a small job never waits for a worker to wake up (on a
// board or VM a sleeping core can take a millisecond to answer), and no worker can still be looking at a
// finished job when the next one is posted.
void ThreadPool::workerLoop() {
  unsigned seen = 0;
  for (;;) {
    Job job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      if (job_.fn == nullptr) continue;  // retired before this worker woke
      job = job_;
      ++active_;
    }
    runChunks(job);
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
  Job job{&fn, begin, end, chunk, chunks};
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = job;
    next_ = 0;
    error_ = nullptr;
    ++generation_;
  }
  wake_.notify_all();
  runChunks(job);
  std::exception_ptr err;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    // Every chunk is taken (runChunks above returned); wait only for workers still running one.
    done_.wait(lock, [&] { return active_ == 0; });
    job_ = Job{};
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
