// OpenCL wrappers of kernels/preprocess.h: global id, bounds check, one call. Built with -DSB_MAP_HALF for
// half storage of the maps (see kernels/common.h).
#include "kernels/preprocess.h"

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
