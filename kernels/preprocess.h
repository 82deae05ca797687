#pragma once
// Preprocessing stages, one pixel per call: mm2meters, bilateralFilter, halfSampleRobust, depth2vertex,
// vertex2normal. Images are row-major; (x, y) is the output pixel. Depth 0 means "no reading".

#include "kernels/common.h"

// mm2meters: the raw sensor image subsampled by `ratio` (the compute size ratio: the top-left pixel of each
// ratio x ratio block, matching Intrinsics::scaled) and converted to metres.
SB_INLINE void mm2meters(SB_GLOBAL sb_map_t* out, int outWidth, SB_GLOBAL const unsigned short* in, int inWidth,
                         int ratio, float metresPerUnit, int x, int y) {
  const unsigned short raw = in[(y * ratio) * inWidth + x * ratio];
  SB_STORE_MAP((float)raw * metresPerUnit, out, y * outWidth + x);
}

// The weight of one bilateralFilter tap: value v (0 = no reading: weight 0), spatial weight `spatial`,
// rangeFactor = -1 / (2 rangeSigma^2).
SB_INLINE float bilateralWeight(float v, float centre, float spatial, float rangeFactor) {
  const float d = v - centre;
  return v > 0.0f ? spatial * sbExp(d * d * rangeFactor) : 0.0f;
}

// bilateralFilter: edge-preserving smoothing. `gaussian` holds the 2*radius+1 spatial weights
// exp(-d^2 / (2 sigma_px^2)); the range weight is exp(-(v - centre)^2 / (2 rangeSigma^2)), rangeSigma in
// metres. Pixels without a reading neither contribute nor get a value.
SB_INLINE void bilateralFilter(SB_GLOBAL sb_map_t* out, SB_GLOBAL const sb_map_t* in, int width, int height,
                               SB_GLOBAL const float* gaussian, int radius, float rangeSigma, int x, int y) {
  const int index = y * width + x;
  const float centre = SB_LOAD_MAP(in, index);
  if (centre <= 0.0f) {
    SB_STORE_MAP(0.0f, out, index);
    return;
  }
  const float rangeFactor = -1.0f / (2.0f * rangeSigma * rangeSigma);
  float weightSum = 0.0f;
  float valueSum = 0.0f;
  for (int dy = -radius; dy <= radius; ++dy) {
    const int yy = sbClampInt(y + dy, 0, height - 1);
    for (int dx = -radius; dx <= radius; ++dx) {
      const int xx = sbClampInt(x + dx, 0, width - 1);
      const float v = SB_LOAD_MAP(in, yy * width + xx);
      const float w = bilateralWeight(v, centre, gaussian[dx + radius] * gaussian[dy + radius], rangeFactor);
      weightSum += w;
      valueSum += w * v;
    }
  }
  SB_STORE_MAP(valueSum / weightSum, out, index);
}

// halfSampleRobust: output pixel (x, y) is the mean of the 2x2 input block at (2x, 2y) over the pixels
// whose depth is within maxDifference (metres) of the block's top-left pixel (which has to be valid).
SB_INLINE void halfSampleRobust(SB_GLOBAL sb_map_t* out, int outWidth, SB_GLOBAL const sb_map_t* in, int inWidth,
                                int inHeight, float maxDifference, int x, int y) {
  const int cx = 2 * x;
  const int cy = 2 * y;
  const float centre = SB_LOAD_MAP(in, cy * inWidth + cx);
  float result = 0.0f;
  if (centre > 0.0f) {
    float sum = 0.0f;
    float count = 0.0f;
    for (int dy = 0; dy <= 1; ++dy) {
      for (int dx = 0; dx <= 1; ++dx) {
        const int xx = sbClampInt(cx + dx, 0, inWidth - 1);
        const int yy = sbClampInt(cy + dy, 0, inHeight - 1);
        const float v = SB_LOAD_MAP(in, yy * inWidth + xx);
        if (v > 0.0f && sbFabs(v - centre) < maxDifference) {
          sum += v;
          count += 1.0f;
        }
      }
    }
    result = sum / count;
  }
  SB_STORE_MAP(result, out, y * outWidth + x);
}

// depth2vertex: back-projects pixel (x, y) with its depth into the camera frame (metres); (0,0,0) when
// there is no reading.
SB_INLINE void depth2vertex(SB_GLOBAL sb_map_t* vertex, SB_GLOBAL const sb_map_t* depth, int width, SbCamera k,
                            int x, int y) {
  const int index = y * width + x;
  const float d = SB_LOAD_MAP(depth, index);
  float3 v = sbMakeFloat3(0.0f, 0.0f, 0.0f);
  if (d > 0.0f) v = sbMakeFloat3(d * ((float)x - k.cx) / k.fx, d * ((float)y - k.cy) / k.fy, d);
  SB_STORE_MAP3(v, vertex, index);
}

// vertex2normal: unit normal from the cross product of the central differences (pointing towards the
// camera); x = SB_INVALID_NORMAL when the pixel or one of its 4 neighbours has no vertex.
SB_INLINE void vertex2normal(SB_GLOBAL sb_map_t* normal, SB_GLOBAL const sb_map_t* vertex, int width, int height,
                             int x, int y) {
  const int index = y * width + x;
  const float3 left = SB_LOAD_MAP3(vertex, y * width + sbClampInt(x - 1, 0, width - 1));
  const float3 right = SB_LOAD_MAP3(vertex, y * width + sbClampInt(x + 1, 0, width - 1));
  const float3 up = SB_LOAD_MAP3(vertex, sbClampInt(y - 1, 0, height - 1) * width + x);
  const float3 down = SB_LOAD_MAP3(vertex, sbClampInt(y + 1, 0, height - 1) * width + x);
  const float3 centre = SB_LOAD_MAP3(vertex, index);
  float3 n = sbMakeFloat3(SB_INVALID_NORMAL, 0.0f, 0.0f);
  if (centre.z > 0.0f && left.z > 0.0f && right.z > 0.0f && up.z > 0.0f && down.z > 0.0f) {
    const float3 c = sbCross(down - up, right - left);
    const float len = sbLength(c);
    if (len > 0.0f) n = c * (1.0f / len);
  }
  SB_STORE_MAP3(n, normal, index);
}
