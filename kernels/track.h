#pragma once
// Projective point-to-plane ICP, one pixel per call: `track` finds the correspondence of an input pixel in
// the reference maps and writes its residual and Jacobian; `reduce` accumulates those into the 6x6 normal
// equations. The solve happens on the host.

#include "kernels/common.h"

// Per-pixel output of `track`: SB_TRACK_STRIDE floats: [0] result code, [1] residual (metres), [2..7] J.
#define SB_TRACK_STRIDE 8
#define SB_TRACK_INLIER 1.0f
#define SB_TRACK_NO_INPUT (-1.0f)      // the input pixel has no normal
#define SB_TRACK_OUTSIDE (-2.0f)       // projects outside the reference image
#define SB_TRACK_NO_REFERENCE (-3.0f)  // the reference pixel has no normal
#define SB_TRACK_TOO_FAR (-4.0f)       // the pair is farther apart than the distance threshold
#define SB_TRACK_BAD_NORMAL (-5.0f)    // the normals disagree (dot below the threshold)

// Reduced sums (SB_REDUCE_SIZE values): [0] sum of squared residuals (m^2), [1..6] J^T e, [7..27] the upper
// triangle of J^T J row by row, [28] inliers, [29] pairs too far, [30] pairs with bad normals, [31] pixels
// without a correspondence (outside or no reference).
#define SB_REDUCE_SIZE 32

// track: input vertex/normal at pixel (x, y) of an input pyramid level (camera frame), moved to the world by
// `cameraToWorld`, projected into the reference maps (world frame, refWidth x refHeight) by `worldToRefPixel`
// (K * inverse(reference pose), homogeneous pixel coordinates).
SB_INLINE void track(SB_GLOBAL float* out, SB_GLOBAL const sb_map_t* inVertex, SB_GLOBAL const sb_map_t* inNormal,
                     int inWidth, SB_GLOBAL const sb_map_t* refVertex, SB_GLOBAL const sb_map_t* refNormal,
                     int refWidth, int refHeight, SbMat34 cameraToWorld, SbMat34 worldToRefPixel,
                     float distanceThreshold, float normalThreshold, int x, int y) {
  const int index = y * inWidth + x;
  SB_GLOBAL float* row = out + SB_TRACK_STRIDE * index;
  const float3 n = SB_LOAD_MAP3(inNormal, index);
  if (n.x == SB_INVALID_NORMAL) {
    row[0] = SB_TRACK_NO_INPUT;
    return;
  }
  const float3 p = sbTransform(cameraToWorld, SB_LOAD_MAP3(inVertex, index));
  const float3 h = sbTransform(worldToRefPixel, p);
  if (h.z <= 0.0f) {
    row[0] = SB_TRACK_OUTSIDE;
    return;
  }
  const float u = sbFloor(h.x / h.z + 0.5f);
  const float v = sbFloor(h.y / h.z + 0.5f);
  if (u < 0.0f || v < 0.0f || u > (float)(refWidth - 1) || v > (float)(refHeight - 1)) {
    row[0] = SB_TRACK_OUTSIDE;
    return;
  }
  const int refIndex = (int)v * refWidth + (int)u;
  const float3 rn = SB_LOAD_MAP3(refNormal, refIndex);
  if (rn.x == SB_INVALID_NORMAL) {
    row[0] = SB_TRACK_NO_REFERENCE;
    return;
  }
  const float3 diff = SB_LOAD_MAP3(refVertex, refIndex) - p;
  if (sbLength(diff) > distanceThreshold) {
    row[0] = SB_TRACK_TOO_FAR;
    return;
  }
  const float3 pn = sbRotate(cameraToWorld, n);
  if (sbDot(pn, rn) < normalThreshold) {
    row[0] = SB_TRACK_BAD_NORMAL;
    return;
  }
  const float3 c = sbCross(p, rn);
  row[0] = SB_TRACK_INLIER;
  row[1] = sbDot(rn, diff);
  row[2] = rn.x;
  row[3] = rn.y;
  row[4] = rn.z;
  row[5] = c.x;
  row[6] = c.y;
  row[7] = c.z;
}

// reduce: adds pixel `index` of the track output to `sums` (SB_REDUCE_SIZE values, private memory).
SB_INLINE void reduce(float* sums, SB_GLOBAL const float* trackOut, int index) {
  SB_GLOBAL const float* row = trackOut + SB_TRACK_STRIDE * index;
  const float result = row[0];
  if (result < 1.0f) {
    if (result == SB_TRACK_TOO_FAR) sums[29] += 1.0f;
    if (result == SB_TRACK_BAD_NORMAL) sums[30] += 1.0f;
    if (result == SB_TRACK_OUTSIDE || result == SB_TRACK_NO_REFERENCE) sums[31] += 1.0f;
    return;
  }
  const float e = row[1];
  sums[0] += e * e;
  for (int i = 0; i < 6; ++i) sums[1 + i] += e * row[2 + i];
  int k = 7;
  for (int i = 0; i < 6; ++i) {
    for (int j = i; j < 6; ++j) {
      sums[k] += row[2 + i] * row[2 + j];
      ++k;
    }
  }
  sums[28] += 1.0f;
}

// The structure of the view (pipeline/tracking_quality.h): a block of pixels of one track output as a single
// track row: an inlier when the block holds any inlier (`count` of them), residual 0, J = jSum / sqrt(count)
// with jSum the sum of their J. reduce() over such rows gives sum over blocks of jSum jSum^T / count: each
// block's mean row weighted by its size, so the structure of the view keeps its weight while normal noise
// that is independent from pixel to pixel averages out over the block (its share falls by about `count`).
SB_INLINE void blockRow(SB_GLOBAL float* row, const float* jSum, float count) {
  if (count < 1.0f) {
    row[0] = SB_TRACK_NO_INPUT;
    return;
  }
  const float scale = 1.0f / sbSqrt(count);
  row[0] = SB_TRACK_INLIER;
  row[1] = 0.0f;
  for (int i = 0; i < 6; ++i) row[2 + i] = jSum[i] * scale;
}

// blockRow for block (bx, by) of `block` x `block` pixels of a track output `width` x `height` (the last
// blocks of a row or column hold what is left); writes row by * ceil(width / block) + bx of `out`.
SB_INLINE void trackBlock(SB_GLOBAL float* out, SB_GLOBAL const float* trackOut, int width, int height, int block,
                          int bx, int by) {
  const int blocksX = (width + block - 1) / block;
  float jSum[6] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
  float count = 0.0f;
  const int x1 = (bx + 1) * block < width ? (bx + 1) * block : width;
  const int y1 = (by + 1) * block < height ? (by + 1) * block : height;
  for (int y = by * block; y < y1; ++y) {
    for (int x = bx * block; x < x1; ++x) {
      SB_GLOBAL const float* row = trackOut + SB_TRACK_STRIDE * (y * width + x);
      if (row[0] != SB_TRACK_INLIER) continue;
      count += 1.0f;
      for (int i = 0; i < 6; ++i) jSum[i] += row[2 + i];
    }
  }
  blockRow(out + SB_TRACK_STRIDE * (by * blocksX + bx), jSum, count);
}
