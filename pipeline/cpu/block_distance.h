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
// then backwards). The neighbours in earlier rows are handled a row at a time through each row's dilation
// (plus one of the minimum over its three x-neighbours, kept once per row) so the loops vectorise, and the
// slices of a pass run in parallel as a wavefront: a slice's row waits only for the three rows of the
// previous slice it reads.

#include <cstdint>
#include <vector>

#include "core/thread_pool.h"

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

// `masks`: n^3 surface masks, x fastest. Writes n^3 distances to `distance`; the same for any thread count.
void computeBlockDistance(const std::vector<uint8_t>& masks, int n, std::vector<uint8_t>& distance,
                          ThreadPool& pool);

}  // namespace sb
