// OpenCL wrappers of kernels/track.h. track: one pixel per work-item. block: one block of track output per
// work-item (kernels/track.h's trackBlock), reduced like pixels. reduce: two passes that leave only the
// SB_REDUCE_SIZE sums for the host to read: reduceKernel sums a strided share of the pixels per work-item
// (kernels/track.h's reduce) and the work-items of a group in local memory, one partial per group;
// reduceFinalKernel sums the partials in group order (in double where the device has cl_khr_fp64, else in
// float with Kahan compensation). Deterministic: the order of every sum is fixed.
#include "kernels/track.h"

#ifdef SB_HAVE_FP64
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
typedef double sb_sum_t;
#else
typedef float sb_sum_t;
#endif

// Work-items per reduce group; the host launches the same number (set by the host as a build option).
#ifndef SB_REDUCE_GROUP
#define SB_REDUCE_GROUP 64
#endif

__kernel void trackKernel(__global float* out, __global const sb_map_t* inVertex, __global const sb_map_t* inNormal,
                          int width, int height, __global const sb_map_t* refVertex, __global const sb_map_t* refNormal,
                          int refWidth, int refHeight, SbMat34 cameraToWorld, SbMat34 worldToRefPixel,
                          float distanceThreshold, float normalThreshold) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x < width && y < height)
    track(out, inVertex, inNormal, width, refVertex, refNormal, refWidth, refHeight, cameraToWorld, worldToRefPixel,
          distanceThreshold, normalThreshold, x, y);
}

__kernel void blockKernel(__global float* out, __global const float* trackOut, int width, int height, int block) {
  const int bx = get_global_id(0), by = get_global_id(1);
  if (bx * block < width && by * block < height) trackBlock(out, trackOut, width, height, block, bx, by);
}

__kernel void reduceKernel(__global float* partial, __global const float* trackOut, int pixels) {
  __local float shared[SB_REDUCE_SIZE * SB_REDUCE_GROUP];
  float sums[SB_REDUCE_SIZE];
  for (int i = 0; i < SB_REDUCE_SIZE; ++i) sums[i] = 0.0f;
  for (int i = get_global_id(0); i < pixels; i += get_global_size(0)) reduce(sums, trackOut, i);
  const int item = get_local_id(0);
  for (int i = 0; i < SB_REDUCE_SIZE; ++i) shared[i * SB_REDUCE_GROUP + item] = sums[i];
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int i = item; i < SB_REDUCE_SIZE; i += SB_REDUCE_GROUP) {
    float sum = 0.0f;
    for (int j = 0; j < SB_REDUCE_GROUP; ++j) sum += shared[i * SB_REDUCE_GROUP + j];
    partial[get_group_id(0) * SB_REDUCE_SIZE + i] = sum;
  }
}

__kernel void reduceFinalKernel(__global sb_sum_t* sums, __global const float* partial, int groups) {
  const int i = get_global_id(0);
  if (i >= SB_REDUCE_SIZE) return;
  sb_sum_t sum = 0;
  sb_sum_t compensation = 0;
  for (int g = 0; g < groups; ++g) {
    const sb_sum_t value = (sb_sum_t)partial[g * SB_REDUCE_SIZE + i] - compensation;
    const sb_sum_t next = sum + value;
    compensation = (next - sum) - value;
    sum = next;
  }
  sums[i] = sum;
}
