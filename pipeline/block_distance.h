#pragma once
// The distance grid of empty-space skipping (kernels/raycast.h, sbSkipByDistance) on an n^3 grid of blocks of
// B^3 voxels.
//
// Integration records per block a surface mask: bit c (c = cx + 2 cy + 4 cz) is set when some voxel of the
// block with a tsdf below the raycast's small-step threshold lies on the block's lower face along every axis
// that c names (voxel index a multiple of B there; bit 0: any such voxel). A block "has surface" for skipping
// when a voxel of it or of the first voxel layer of its upper neighbours (voxels B*b .. B*b + B per axis) is
// below the threshold: that is bit c of the block b + c, for any c.
//
// The distance of a block is the Chebyshev distance in blocks to the nearest block with surface (0 for such a
// block, kNoSurfaceDistance when there is none), computed exactly by the two raster passes of the chessboard
// distance transform (each block takes the minimum over its 13 already visited neighbours plus one, forwards
// then backwards), with the 12 neighbours in earlier rows handled a row at a time so the loops vectorise.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace sb {

constexpr uint8_t kNoSurfaceDistance = 255;

// The mask bits that a voxel below the threshold sets in its block, from which lower faces it lies on:
// `faces` = (x % B == 0) + 2 (y % B == 0) + 4 (z % B == 0). Bit c is set when c names only such axes.
inline uint8_t surfaceMaskBits(int faces) {
  uint8_t bits = 0;
  for (int c = 0; c < 8; ++c)
    if ((c & ~faces) == 0) bits = static_cast<uint8_t>(bits | (1u << c));
  return bits;
}

// `masks`: n^3 surface masks, x fastest. Writes n^3 distances to `distance`.
inline void computeBlockDistance(const std::vector<uint8_t>& masks, int n, std::vector<uint8_t>& distance) {
  const size_t nn = static_cast<size_t>(n) * n;
  distance.resize(nn * n);
  // Seeds, a row at a time: bit c of the mask of block (x, y, z) + c, for the c whose block exists.
  std::vector<uint8_t> surface(static_cast<size_t>(n));
  for (int z = 0; z < n; ++z) {
    for (int y = 0; y < n; ++y) {
      std::fill(surface.begin(), surface.end(), 0);
      for (int c = 0; c < 8; ++c) {
        const int cx = c & 1, qy = y + ((c >> 1) & 1), qz = z + (c >> 2);
        if (qy >= n || qz >= n) continue;
        const uint8_t* m = &masks[static_cast<size_t>(qy) * n + qz * nn] + cx;
        for (int x = 0; x < n - cx; ++x) surface[x] |= static_cast<uint8_t>((m[x] >> c) & 1u);
      }
      uint8_t* row = &distance[static_cast<size_t>(y) * n + z * nn];
      for (int x = 0; x < n; ++x) row[x] = surface[x] ? 0 : kNoSurfaceDistance;
    }
  }
  // row = min(row, other + 1) over the three x-neighbours (-1, 0, +1) of `other`, saturating at 255; the
  // interior without bound checks so that it vectorises.
  const auto plusOne = [](uint8_t m) { return static_cast<uint8_t>(m + (m < kNoSurfaceDistance ? 1 : 0)); };
  const auto relax = [&](uint8_t* row, const uint8_t* other) {
    if (n == 1) {
      row[0] = std::min(row[0], plusOne(other[0]));
      return;
    }
    row[0] = std::min(row[0], plusOne(std::min(other[0], other[1])));
    for (int x = 1; x < n - 1; ++x)
      row[x] = std::min(row[x], plusOne(std::min(other[x - 1], std::min(other[x], other[x + 1]))));
    row[n - 1] = std::min(row[n - 1], plusOne(std::min(other[n - 2], other[n - 1])));
  };
  // Forwards: neighbours in the previous slice (rows y-1, y, y+1) and the previous row, then x-1 in order.
  for (int z = 0; z < n; ++z) {
    for (int y = 0; y < n; ++y) {
      uint8_t* row = &distance[static_cast<size_t>(y) * n + z * nn];
      if (z > 0)
        for (int dy = -1; dy <= 1; ++dy)
          if (y + dy >= 0 && y + dy < n)
            relax(row, &distance[static_cast<size_t>(y + dy) * n + (z - 1) * nn]);
      if (y > 0) relax(row, &distance[static_cast<size_t>(y - 1) * n + z * nn]);
      for (int x = 1; x < n; ++x)
        row[x] = std::min<uint8_t>(
            row[x], static_cast<uint8_t>(row[x - 1] + (row[x - 1] < kNoSurfaceDistance ? 1 : 0)));
    }
  }
  // Backwards: the mirror image.
  for (int z = n - 1; z >= 0; --z) {
    for (int y = n - 1; y >= 0; --y) {
      uint8_t* row = &distance[static_cast<size_t>(y) * n + z * nn];
      if (z + 1 < n)
        for (int dy = -1; dy <= 1; ++dy)
          if (y + dy >= 0 && y + dy < n)
            relax(row, &distance[static_cast<size_t>(y + dy) * n + (z + 1) * nn]);
      if (y + 1 < n) relax(row, &distance[static_cast<size_t>(y + 1) * n + z * nn]);
      for (int x = n - 2; x >= 0; --x)
        row[x] = std::min<uint8_t>(
            row[x], static_cast<uint8_t>(row[x + 1] + (row[x + 1] < kNoSurfaceDistance ? 1 : 0)));
    }
  }
}

}  // namespace sb
