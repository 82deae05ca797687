// The distance grid of empty-space skipping (pipeline/block_distance.h) against its definition, by brute
// force, for several pool sizes (the slices are seeded over the pool's threads) and caps (the distance is
// min(true distance, cap)), and against a breadth-first search over the 26 neighbours for rows of more than one
// 64-bit word. Also built with ThreadSanitizer
// (test_block_distance_tsan).

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <vector>

#include "core/thread_pool.h"
#include "pipeline/block_distance.h"

TEST_CASE("computeBlockDistance is the Chebyshev distance to the nearest block with surface",
          "[pipeline][raycast]") {
  const int n = GENERATE(1, 2, 9, 17);
  const uint32_t density = GENERATE(3u, 40u, 100000u);  // about one mask in `density` is non-zero
  std::vector<uint8_t> masks(static_cast<size_t>(n) * n * n, 0);
  uint32_t seed = 99u + n + density;
  for (uint8_t& m : masks) {
    seed = seed * 1664525u + 1013904223u;
    if ((seed >> 8) % density == 0) m = static_cast<uint8_t>(seed >> 24);
  }
  // Slices run as a wavefront over the pool's threads: the result must not depend on how many.
  const unsigned threads = GENERATE(1u, 2u, 5u);
  const int cap = GENERATE(int(sb::kNoSurfaceDistance), sb::kMaxBlockDistance, 3, 1);
  sb::ThreadPool pool(threads);
  std::vector<uint8_t> distance;
  sb::computeBlockDistance(masks, n, distance, pool, cap);
  // The definition, by brute force: block b has surface when bit c of the mask of block b + c is set.
  std::vector<int> surface;
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        for (int c = 0; c < 8; ++c) {
          const int qx = x + (c & 1), qy = y + ((c >> 1) & 1), qz = z + (c >> 2);
          if (qx < n && qy < n && qz < n && ((masks[qx + (qy + qz * n) * n] >> c) & 1)) {
            surface.push_back(x + (y + z * n) * n);
            break;
          }
        }
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        int expected = sb::kNoSurfaceDistance;
        for (const int s : surface) {
          const int sx = s % n, sy = (s / n) % n, sz = s / (n * n);
          expected = std::min(expected, std::max({std::abs(sx - x), std::abs(sy - y), std::abs(sz - z)}));
        }
        INFO("n " << n << ", cap " << cap << ", block " << x << " " << y << " " << z);
        REQUIRE(int(distance[x + (y + z * n) * n]) == std::min(expected, cap));
      }
}

// Rows of more than one word (n > 64): bits carried across word boundaries along x, the partial last word, and
// distances of more than 64 blocks. The reference is a breadth-first search over the 26 neighbours, whose
// path length is the Chebyshev distance.
TEST_CASE("computeBlockDistance across words of a row and far from the surface", "[pipeline][raycast]") {
  const int n = GENERATE(64, 66, 130);
  const int pattern = GENERATE(0, 1, 2);  // random sparse, one block at the x = 63/64 seam, one corner
  const size_t total = static_cast<size_t>(n) * n * n;
  std::vector<uint8_t> masks(total, 0);
  if (pattern == 0) {
    uint32_t seed = 7u + n;
    for (uint8_t& m : masks) {
      seed = seed * 1664525u + 1013904223u;
      if ((seed >> 8) % 3000 == 0) m = static_cast<uint8_t>(seed >> 24);
    }
  } else if (pattern == 1) {
    masks[63 + (n / 2 + (n / 3) * static_cast<size_t>(n)) * n] = 1;  // bit 0: block (63, n/2, n/3) itself
  } else {
    masks[0] = 1;  // block 0 only: distances up to n - 1 (129 for n = 130)
  }
  const int cap = GENERATE(int(sb::kNoSurfaceDistance), sb::kMaxBlockDistance);
  sb::ThreadPool pool(2);
  std::vector<uint8_t> distance;
  sb::computeBlockDistance(masks, n, distance, pool, cap);
  std::vector<int> expected(total, sb::kNoSurfaceDistance);
  std::deque<size_t> queue;
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        for (int c = 0; c < 8; ++c) {
          const int qx = x + (c & 1), qy = y + ((c >> 1) & 1), qz = z + (c >> 2);
          if (qx < n && qy < n && qz < n && ((masks[qx + (qy + static_cast<size_t>(qz) * n) * n] >> c) & 1)) {
            const size_t b = x + (y + static_cast<size_t>(z) * n) * n;
            expected[b] = 0;
            queue.push_back(b);
            break;
          }
        }
  while (!queue.empty()) {
    const size_t b = queue.front();
    queue.pop_front();
    const int x = static_cast<int>(b % n), y = static_cast<int>((b / n) % n), z = static_cast<int>(b / n / n);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int qx = x + dx, qy = y + dy, qz = z + dz;
          if (qx < 0 || qy < 0 || qz < 0 || qx >= n || qy >= n || qz >= n) continue;
          const size_t q = qx + (qy + static_cast<size_t>(qz) * n) * n;
          if (expected[q] != sb::kNoSurfaceDistance) continue;
          expected[q] = expected[b] + 1;
          queue.push_back(q);
        }
  }
  size_t wrong = 0, first = total;
  for (size_t b = 0; b < total; ++b)
    if (int(distance[b]) != std::min(expected[b], cap)) {
      ++wrong;
      if (first == total) first = b;
    }
  INFO("n " << n << ", cap " << cap << ", pattern " << pattern << ", first wrong block " << first << " of " << wrong);
  REQUIRE(wrong == 0);
}
