#pragma once
// The distance grid of empty-space skipping (kernels/raycast.h, sbSkipByDistance) on an n^3 grid of blocks of
// B^3 voxels, computed on the host by both backends from the surface masks their integrate leaves
// (kernels/raycast.h, sbSurfaceMaskBits: a block "has surface" when bit c of the mask of block b + c is set,
// for any c).
//
// The distance of a block is the Chebyshev distance in blocks to the nearest block with surface (0 for such a
// block), capped at `maxDistance` (and at kNoSurfaceDistance), which is also the distance of every block when
// there is no surface. A lower distance than the true one only costs the raycast lookups (sbSkipByDistance
// skips a box of that radius), never a sample: the maps do not depend on it. The cap bounds the cost: the
// blocks with surface as bits (64 blocks of a row per word, seeded from the masks' bit planes by 8 x 8 bit
// transposes) are dilated by one block per radius r (a shift-or along x, an or of neighbouring rows and
// slices), and the blocks each dilation adds are written as r, so a grid costs about maxDistance times a few
// word operations per 64 blocks plus one byte store per block. Issue 43, 64^3 blocks, 7-Scenes: 5.9 M
// instructions per grid, where the two raster passes of the chamfer transform it replaces took 15.2 M (a
// quarter of an adaptive integration).

#include <cmath>
#include <cstdint>
#include <vector>

#include "core/thread_pool.h"
#include "kernels/volume.h"

namespace sb {

constexpr uint8_t kNoSurfaceDistance = 255;

// The raw (stored int16) tsdf below which a voxel counts as surface for skipping: stored < this exactly when
// the voxel's tsdf is below the raycast's small-step threshold `smallStepBelow` (PipelineConfig's
// raycast_small_step_below), where the march would leave its large step.
inline int16_t surfaceTsdfBelow(float smallStepBelow) {
  return static_cast<int16_t>(std::ceil(smallStepBelow * SB_TSDF_SCALE));
}

// Past this many blocks the distance is not worth its cost: a ray through empty space then looks the grid up
// every kMaxBlockDistance blocks (16 blocks, 64 voxels: a quarter of the default volume) instead of once.
constexpr int kMaxBlockDistance = 16;

// `masks`: n^3 surface masks, x fastest. Writes n^3 distances to `distance`; the same for any thread count
// (`pool` seeds the slices in parallel; the radii run on the calling thread).
void computeBlockDistance(const std::vector<uint8_t>& masks, int n, std::vector<uint8_t>& distance,
                          ThreadPool& pool, int maxDistance = kMaxBlockDistance);

}  // namespace sb
