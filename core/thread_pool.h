#pragma once
// A small fixed-size thread pool for data-parallel loops. Work is split into fixed chunks whose boundaries
// depend only on the range and the chunk size, never on the thread count, so a reduction that stores one
// partial result per chunk and sums the partials in chunk order is bit-identical for any number of threads.

#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace sb {

class ThreadPool {
 public:
  // threads = 0 means std::thread::hardware_concurrency(). The calling thread also works, so a pool of
  // N threads starts N-1 workers.
  explicit ThreadPool(unsigned threads = 0);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  unsigned threadCount() const { return static_cast<unsigned>(workers_.size()) + 1; }

  // Number of chunks parallelFor uses for [begin, end) with the given chunk size.
  static int chunkCount(int begin, int end, int chunk) { return end <= begin ? 0 : (end - begin + chunk - 1) / chunk; }

  // Calls fn(chunkIndex, chunkBegin, chunkEnd) for every chunk of [begin, end); returns when all are done.
  // Chunks are started in increasing order, so a chunk may wait for an earlier one (it is running or done),
  // never for a later one. Exceptions thrown by fn are rethrown here (the first one).
  void parallelFor(int begin, int end, int chunk, const std::function<void(int, int, int)>& fn);

  // The process-wide pool used by the CPU backend and tools.
  static ThreadPool& global();
  // Sets the size of the global pool; only valid before its first use.
  static void setGlobalThreads(unsigned threads);

 private:
  struct Job {
    const std::function<void(int, int, int)>* fn = nullptr;
    int begin = 0, end = 0, chunk = 1, chunks = 0;
  };
  void workerLoop();
  void runChunks(const Job& job);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;
  Job job_;                 // guarded by mutex_; workers copy it when they wake
  std::atomic<int> next_{0};  // next chunk to take
  unsigned active_ = 0;       // workers running chunks of the posted job (guarded by mutex_)
  unsigned generation_ = 0;
  bool stop_ = false;
  std::exception_ptr error_;
};

}  // namespace sb
