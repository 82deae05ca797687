// OpenCL wrappers of kernels/volume.h: volume initialisation, integrate (one voxel per work-item) and the
// empty-space skipping grids (kernels/raycast.h's sbSkipTo): a block's flag is set by any of its voxels that
// integrate leaves near a surface (every writer stores the same 1: no atomics, so nothing depends on
// cross-device coherence), a coarse cell's flag by any of its blocks. Flags are never cleared: a block whose
// surface has gone keeps its flag (fewer skips, never a wrong one). The CPU backend differs: it recomputes a
// block's surface mask whenever an integration visits all of the block's voxels, and skips by the distance to
// the nearest block with surface (pipeline/cpu/block_distance.h).
#include "kernels/volume.h"

__kernel void initVolumeKernel(__global short* volume, int voxels) {
  const int i = get_global_id(0);
  if (i < voxels) {
    volume[2 * i] = (short)SB_TSDF_SCALE;
    volume[2 * i + 1] = 0;
  }
}

__kernel void integrateKernel(__global short* volume, int resolution, float size, SbMat34 worldToCamera,
                              __global const sb_map_t* depth, int width, int height, SbCamera k, float mu, int maxWeight,
                              __global uchar* blockFlags) {
  const int x = get_global_id(0), y = get_global_id(1), z = get_global_id(2);
  if (x < resolution && y < resolution && z < resolution &&
      integrate(volume, resolution, size, worldToCamera, depth, width, height, k, mu, maxWeight, x, y, z)) {
    const int b = resolution >> SB_BLOCK_SHIFT;
    blockFlags[(x >> SB_BLOCK_SHIFT) + (y >> SB_BLOCK_SHIFT) * b + (z >> SB_BLOCK_SHIFT) * b * b] = 1;
  }
}

// One work-item per coarse cell (cells of (1 << SB_SUPER_SHIFT)^3 voxels); `blocks`: blocks per side.
__kernel void superFlagsKernel(__global uchar* superFlags, __global const uchar* blockFlags, int blocks) {
  const int ratio = 1 << (SB_SUPER_SHIFT - SB_BLOCK_SHIFT);
  const int supers = blocks / ratio;
  const int x = get_global_id(0), y = get_global_id(1), z = get_global_id(2);
  if (x >= supers || y >= supers || z >= supers) return;
  const int cell = x + y * supers + z * supers * supers;
  if (superFlags[cell]) return;
  for (int bz = z * ratio; bz < (z + 1) * ratio; ++bz)
    for (int by = y * ratio; by < (y + 1) * ratio; ++by)
      for (int bx = x * ratio; bx < (x + 1) * ratio; ++bx)
        if (blockFlags[bx + by * blocks + bz * blocks * blocks]) {
          superFlags[cell] = 1;
          return;
        }
}
