// The distance grid of empty-space skipping (pipeline/block_distance.h) against its definition, by brute
// force, for several pool sizes (the passes run as a wavefront over the pool's threads). Also built with
// ThreadSanitizer (test_block_distance_tsan).

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <cstdlib>
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
  sb::ThreadPool pool(threads);
  std::vector<uint8_t> distance;
  sb::computeBlockDistance(masks, n, distance, pool);
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
        INFO("n " << n << ", block " << x << " " << y << " " << z);
        REQUIRE(int(distance[x + (y + z * n) * n]) == expected);
      }
}
