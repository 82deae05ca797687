#include "pipeline/block_distance.h"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <memory>
#include <thread>

namespace sb {

namespace {

uint8_t plusOne(uint8_t m) {
  return static_cast<uint8_t>(m + (m < kNoSurfaceDistance ? 1 : 0));
}

// out[x] = plusOne(min(row[x - 1], row[x], row[x + 1])), over the neighbours that exist.
void dilateRow(const uint8_t* row, int n, uint8_t* out) {
  if (n == 1) {
    out[0] = plusOne(row[0]);
    return;
  }
  out[0] = plusOne(std::min(row[0], row[1]));
  for (int x = 1; x < n - 1; ++x) out[x] = plusOne(std::min(row[x - 1], std::min(row[x], row[x + 1])));
  out[n - 1] = plusOne(std::min(row[n - 2], row[n - 1]));
}

// Row (y, z) of the seeds: 0 where bit c of the mask of block (x, y, z) + c is set for some c whose block
// exists, else kNoSurfaceDistance. (A function of its own: inside the pool's lambdas a byte store may alias
// the captured sizes, and GCC then vectorises none of these loops.)
void seedRow(const uint8_t* masks, int n, int y, int z, uint8_t* row) {
  const size_t nn = static_cast<size_t>(n) * n;
  std::fill(row, row + n, 0);
  for (int c = 0; c < 8; ++c) {
    const int cx = c & 1, qy = y + ((c >> 1) & 1), qz = z + (c >> 2);
    if (qy >= n || qz >= n) continue;
    const uint8_t* m = masks + static_cast<size_t>(qy) * n + qz * nn + cx;
    for (int x = 0; x < n - cx; ++x) row[x] |= static_cast<uint8_t>((m[x] >> c) & 1u);
  }
  for (int x = 0; x < n; ++x) row[x] = row[x] ? 0 : kNoSurfaceDistance;
}

void minInto(uint8_t* row, const uint8_t* other, int n) {
  for (int x = 0; x < n; ++x) row[x] = std::min(row[x], other[x]);
}

// The x-neighbour already visited in a raster pass along `direction` (+1: x - 1, in order; -1: x + 1): a
// serial chain, kept short by working in int, where min(row, 255 + 1) = row needs no saturation test.
void scanRow(uint8_t* row, int n, int direction) {
  const int step = direction > 0 ? 1 : -1;
  int x = direction > 0 ? 0 : n - 1;
  int previous = row[x];
  for (int i = 1; i < n; ++i) {
    x += step;
    previous = std::min(static_cast<int>(row[x]), previous + 1);
    row[x] = static_cast<uint8_t>(previous);
  }
}

// Waits until `rows` >= target. The slice being waited for is always in progress on another thread or done:
// the pool starts chunks in increasing order and a slice waits only for the one started before it.
void waitRows(const std::atomic<int>& rows, int target) {
  for (int spins = 0; rows.load(std::memory_order_acquire) < target; ++spins)
    if (spins >= 64) std::this_thread::yield();
}

}  // namespace

void computeBlockDistance(const std::vector<uint8_t>& masks, int n, std::vector<uint8_t>& distance,
                          ThreadPool& pool) {
  const size_t nn = static_cast<size_t>(n) * n;
  distance.resize(nn * n);
  std::vector<uint8_t> dilated(nn * n);  // per row: dilateRow() of its distances as last written
  const std::unique_ptr<std::atomic<int>[]> rowsDone(new std::atomic<int>[static_cast<size_t>(n)]);
  const auto at = [n, nn](std::vector<uint8_t>& grid, int y, int z) {
    return &grid[static_cast<size_t>(y) * n + static_cast<size_t>(z) * nn];
  };
  // Pass `direction` (+1 forwards, -1 backwards), slices in that order, one chunk each: per row (in that
  // order) the seeds (first pass only), the 9 neighbours in the previous slice (3 rows) and the 3 in the
  // previous row through their dilations, then the x-neighbour already visited. rowsDone[z]: how many rows of
  // slice z are done, counted in pass order.
  const auto pass = [&](int direction) {
    for (int z = 0; z < n; ++z) rowsDone[z].store(0, std::memory_order_relaxed);
    pool.parallelFor(0, n, 1, [&](int, int c, int) {
      const int z = direction > 0 ? c : n - 1 - c, previousSlice = z - direction;
      for (int i = 0; i < n; ++i) {
        const int y = direction > 0 ? i : n - 1 - i;
        uint8_t* row = at(distance, y, z);
        if (direction > 0) seedRow(masks.data(), n, y, z, row);
        if (previousSlice >= 0 && previousSlice < n) {
          waitRows(rowsDone[previousSlice], std::min(i + 2, n));
          for (int dy = -1; dy <= 1; ++dy)
            if (y + dy >= 0 && y + dy < n) minInto(row, at(dilated, y + dy, previousSlice), n);
        }
        if (i > 0) minInto(row, at(dilated, y - direction, z), n);
        scanRow(row, n, direction);
        dilateRow(row, n, at(dilated, y, z));
        rowsDone[z].store(i + 1, std::memory_order_release);
      }
    });
  };
  pass(+1);
  pass(-1);
}

}  // namespace sb
