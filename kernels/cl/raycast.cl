// OpenCL wrappers of kernels/raycast.h: raycast and render, one pixel per work-item.
#include "kernels/raycast.h"

// `blockDistance`: the distances of blocks of (1 << SB_SKIP_SHIFT)^3 voxels, or NULL: no empty-space skipping.
// `rayBounds`: per tile of SB_RAY_BOUNDS_TILE^2 pixels, tMin and tMax (pipeline/ray_bounds.h), or NULL.
__kernel void raycastKernel(__global sb_map_t* vertex, __global sb_map_t* normal, int width, int height,
                            __global const short* volume, int resolution, SbVoxelOffset offset, float size,
                            __global const uchar* blockDistance, __global const float* rayBounds, int boundsColumns,
                            SbMat34 cameraToWorld, SbCamera k, float nearPlane, float farPlane, float largeStep,
                            float smallStep, float smallStepBelow) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x < width && y < height)
    raycast(vertex, normal, width, volume, resolution, offset, size, blockDistance, rayBounds, boundsColumns,
            cameraToWorld, k, nearPlane, farPlane, largeStep, smallStep, smallStepBelow, x, y);
}

// The moving volume: raycast maps from the volume's frame to the world frame (kernels/raycast.h, offsetVertex).
__kernel void offsetVertexKernel(__global sb_map_t* vertex, __global const sb_map_t* normal, int width, int height,
                                 float4 corner) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x < width && y < height) offsetVertex(vertex, normal, corner.xyz, y * width + x);
}

__kernel void renderKernel(__global uchar* out, __global const sb_map_t* vertex, __global const sb_map_t* normal,
                           int width, int height, float4 light, float ambient) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x < width && y < height) render(out, vertex, normal, width, light.xyz, ambient, x, y);
}
