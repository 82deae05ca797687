#pragma once
// The distance grid of empty-space skipping (kernels/raycast.h, sbSkipByDistance) on an n^3 grid of blocks of
// B^3 voxels, computed on the host by both backends from the surface masks their integrate leaves
// (kernels/raycast.h, sbSurfaceMaskBits: a block "has surface" when bit c of the mask of block b + c is set,
// for any c).
//
// The distance of a block is the Chebyshev distance in blocks to the nearest block with surface (0 for such a
// block, kNoSurfaceDistance when there is none), computed exactly by the two raster passes of the chessboard
// distance transform (each block takes the minimum over its 13 already visited neighbours plus one, forwards
// then backwards). The neighbours in earlier rows are handled a row at a time through each row's dilation
// (plus one of the minimum over its three x-neighbours, kept once per row) so the loops vectorise, and the
// slices of a pass run in parallel as a wavefront: a slice's row waits only for the three rows of the
// previous slice it reads.

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

// `masks`: n^3 surface masks, x fastest. Writes n^3 distances to `distance`; the same for any thread count.
void computeBlockDistance(const std::vector<uint8_t>& masks, int n, std::vector<uint8_t>& distance,
                          ThreadPool& pool);

}  // namespace sb
