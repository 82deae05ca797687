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

__kernel void integrateKernel(__global short* volume, int resolution, float size, SbMat34 worldToCamera,
                              __global const sb_map_t* depth, int width, int height, SbCamera k, float mu,
                              int maxWeight) {
  const int x = get_global_id(0), y = get_global_id(1), z = get_global_id(2);
  if (x < resolution && y < resolution && z < resolution)
    integrate(volume, resolution, size, worldToCamera, depth, width, height, k, mu, maxWeight, x, y, z);
}

// `blocks`: blocks per side (resolution >> SB_SKIP_SHIFT); `below`: the raw tsdf threshold.
__kernel void surfaceMaskKernel(__global uchar* masks, __global const short* volume, int resolution, int blocks,
                                int below) {
  const int x = get_global_id(0), y = get_global_id(1), z = get_global_id(2);
  if (x < blocks && y < blocks && z < blocks)
    masks[x + y * blocks + z * blocks * blocks] =
        sbBlockSurfaceMask(volume, resolution, SB_SKIP_SHIFT, below, x, y, z);
}
