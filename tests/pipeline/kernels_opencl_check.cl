// Compile check: the kernels/ headers are valid OpenCL C 1.2 (with and without -DSB_MAP_HALF). Thin
// wrappers in the form the OpenCL backend will use: global id, bounds check, one call.
#include "kernels/preprocess.h"
#include "kernels/raycast.h"
#include "kernels/track.h"

__kernel void mm2metersKernel(__global sb_map_t* out, int width, int height, __global const ushort* in, int inWidth,
                              int ratio, float metresPerUnit) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x < width && y < height) mm2meters(out, width, in, inWidth, ratio, metresPerUnit, x, y);
}
__kernel void bilateralFilterKernel(__global sb_map_t* out, __global const sb_map_t* in, int width, int height,
                                    __global const float* gaussian, int radius, float rangeSigma) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x < width && y < height) bilateralFilter(out, in, width, height, gaussian, radius, rangeSigma, x, y);
}
__kernel void halfSampleRobustKernel(__global sb_map_t* out, int outWidth, int outHeight, __global const sb_map_t* in,
                                     int inWidth, int inHeight, float maxDifference) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x < outWidth && y < outHeight) halfSampleRobust(out, outWidth, in, inWidth, inHeight, maxDifference, x, y);
}
__kernel void depth2vertexKernel(__global sb_map_t* vertex, __global const sb_map_t* depth, int width, int height,
                                 SbCamera k) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x < width && y < height) depth2vertex(vertex, depth, width, k, x, y);
}
__kernel void vertex2normalKernel(__global sb_map_t* normal, __global const sb_map_t* vertex, int width, int height) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x < width && y < height) vertex2normal(normal, vertex, width, height, x, y);
}
__kernel void trackKernel(__global float* out, __global const sb_map_t* inVertex, __global const sb_map_t* inNormal,
                          int width, int height, __global const sb_map_t* refVertex, __global const sb_map_t* refNormal,
                          int refWidth, int refHeight, SbMat34 cameraToWorld, SbMat34 worldToRefPixel,
                          float distanceThreshold, float normalThreshold) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x < width && y < height)
    track(out, inVertex, inNormal, width, refVertex, refNormal, refWidth, refHeight, cameraToWorld, worldToRefPixel,
          distanceThreshold, normalThreshold, x, y);
}
__kernel void reduceKernel(__global float* partial, __global const float* trackOut, int pixels) {
  float sums[SB_REDUCE_SIZE];
  for (int i = 0; i < SB_REDUCE_SIZE; ++i) sums[i] = 0.0f;
  for (int i = get_global_id(0); i < pixels; i += get_global_size(0)) reduce(sums, trackOut, i);
  for (int i = 0; i < SB_REDUCE_SIZE; ++i) partial[get_global_id(0) * SB_REDUCE_SIZE + i] = sums[i];
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
__kernel void raycastKernel(__global sb_map_t* vertex, __global sb_map_t* normal, int width, int height,
                            __global const short* volume, int resolution, float size, __global const uchar* blockFlags,
                            __global const uchar* superFlags, SbMat34 cameraToWorld, SbCamera k, float nearPlane,
                            float farPlane, float largeStep, float smallStep, float smallStepBelow) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x < width && y < height)
    raycast(vertex, normal, width, volume, resolution, size, blockFlags, superFlags, cameraToWorld, k, nearPlane,
            farPlane, largeStep, smallStep, smallStepBelow, x, y);
}
__kernel void renderKernel(__global uchar* out, __global const sb_map_t* vertex, __global const sb_map_t* normal,
                           int width, int height, float4 light, float ambient) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x < width && y < height) render(out, vertex, normal, width, light.xyz, ambient, x, y);
}
