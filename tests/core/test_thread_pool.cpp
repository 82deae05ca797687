// The thread pool: deterministic chunking, every chunk run once, errors propagated. Also built with
// ThreadSanitizer (test_thread_pool_tsan) so that races in the pool itself are caught.
#include <catch2/catch.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <numeric>
#include <thread>
#include <vector>

#include "core/error.h"
#include "core/thread_pool.h"

using namespace sb;

TEST_CASE("thread pool chunk reductions are identical for any thread count", "[core][thread_pool]") {
  std::vector<float> values(100003);
  for (size_t i = 0; i < values.size(); ++i) values[i] = 1.0f / static_cast<float>(i + 1) * ((i % 3) ? 1.f : -1.f);
  auto reduce = [&](unsigned threads) {
    ThreadPool pool(threads);
    const int chunk = 997;
    std::vector<float> partial(ThreadPool::chunkCount(0, static_cast<int>(values.size()), chunk));
    pool.parallelFor(0, static_cast<int>(values.size()), chunk, [&](int c, int b, int e) {
      float s = 0;
      for (int i = b; i < e; ++i) s += values[i];
      partial[c] = s;
    });
    return std::accumulate(partial.begin(), partial.end(), 0.0f);
  };
  const float one = reduce(1);
  CHECK(reduce(2) == one);
  CHECK(reduce(5) == one);
  // Repeated use of one pool must run every chunk exactly once.
  // Many short jobs back to back on more threads than cores: the pattern where a late-waking worker
  // could still be reading the previous job.
  ThreadPool pool(4);
  for (int round = 0; round < 3000; ++round) {
    std::vector<int> hits(200, 0);
    pool.parallelFor(0, 200, 1, [&](int, int b, int e) {
      for (int i = b; i < e; ++i) ++hits[i];
    });
    REQUIRE(std::all_of(hits.begin(), hits.end(), [](int h) { return h == 1; }));
  }
  CHECK_THROWS_AS(pool.parallelFor(0, 10, 1, [](int c, int, int) {
    if (c == 5) throw Error("boom");
  }), Error);
}

// A job retires as soon as its chunks are done and no worker is inside one; a worker that wakes later must
// find nothing to do. Pauses between jobs let the workers fall asleep, so most jobs are finished by the
// caller alone while the workers are still waking: every chunk must still run exactly once, and a slow
// chunk taken by a worker must hold the caller until it ends.
TEST_CASE("thread pool jobs retire without waiting for sleeping workers", "[core][thread_pool]") {
  ThreadPool pool(3);
  std::atomic<int> slowDone{0};
  for (int round = 0; round < 300; ++round) {
    std::vector<int> hits(4, 0);
    const bool slow = round % 3 == 0;
    pool.parallelFor(0, 4, 1, [&](int c, int b, int e) {
      if (slow && c == 3) {
        std::this_thread::sleep_for(std::chrono::microseconds(300));
        slowDone.fetch_add(1);
      }
      for (int i = b; i < e; ++i) ++hits[i];
    });
    REQUIRE(std::all_of(hits.begin(), hits.end(), [](int h) { return h == 1; }));
    REQUIRE(slowDone.load() == (round / 3) + 1);
    if (round % 2) std::this_thread::sleep_for(std::chrono::microseconds(200 + 37 * (round % 11)));
  }
}
