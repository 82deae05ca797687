// OpenCL wrappers of kernels/volume.h and kernels/raycast.h: volume initialisation, integrate (one voxel per
// work-item) and the surface masks of empty-space skipping (one block of (1 << SB_SKIP_SHIFT)^3 voxels per
// work-item, kernels/raycast.h's sbBlockSurfaceMask), recomputed from the whole volume after every
// integration: a block whose surface has gone loses its mask. The host turns the masks into the block
// distances that raycast skips by (pipeline/block_distance.h), as the CPU backend does.
#include "kernels/raycast.h"

__kernel void initVolumeKernel(__global short* volume, int voxels) {
  const int i = get_global_id(0);
  if (i < voxels) {
    volume[2 * i] = (short)SB_TSDF_SCALE;
    volume[2 * i + 1] = 0;
  }
}

// One logical voxel per work-item; `offset`: the moving volume's cyclic offset (kernels/volume.h).
__kernel void integrateKernel(__global short* volume, int resolution, SbVoxelOffset offset, float size,
                              SbMat34 worldToCamera, __global const sb_map_t* depth, int width, int height,
                              SbCamera k, float mu, int maxWeight) {
  const int x = get_global_id(0), y = get_global_id(1), z = get_global_id(2);
  if (x < resolution && y < resolution && z < resolution)
    integrate(volume, resolution, offset, size, worldToCamera, depth, width, height, k, mu, maxWeight, x, y, z);
}

// The slab that leaves a moving volume: `count` physical planes normal to `axis` from `first`, cleared.
__kernel void clearSlabKernel(__global short* volume, int resolution, int axis, int first, int count) {
  const int u = get_global_id(0), v = get_global_id(1), w = get_global_id(2);
  if (u < count && v < resolution && w < resolution) clearSlab(volume, resolution, axis, first, u, v, w);
}

// `blocks`: blocks per side (resolution >> SB_SKIP_SHIFT); `below`: the raw tsdf threshold.
__kernel void surfaceMaskKernel(__global uchar* masks, __global const short* volume, int resolution,
                                SbVoxelOffset offset, int blocks, int below) {
  const int x = get_global_id(0), y = get_global_id(1), z = get_global_id(2);
  if (x < blocks && y < blocks && z < blocks)
    masks[x + y * blocks + z * blocks * blocks] =
        sbBlockSurfaceMask(volume, resolution, offset, SB_SKIP_SHIFT, below, x, y, z);
}
