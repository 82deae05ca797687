#pragma once
// raycast: the model surface seen from a pose, one pixel per call (the reference for the next frame's ICP);
// render: a shaded image of raycast maps, for output only.

#include "kernels/volume.h"

// Empty-space skipping. `blockFlags` holds one byte per block of (1 << SB_BLOCK_SHIFT)^3 voxels, non-zero when
// some voxel of the block stores a tsdf below +1. When every voxel that the trilinear interpolation at `pos`
// reads lies in blocks without surface, the interpolation is exactly +1 there and stays so while the ray
// remains in the box whose interpolation cells use only those blocks: returns the ray parameter where the ray
// leaves that box. Returns -1 when a block with surface is involved.
// `shift`: log2 of the block side in voxels (SB_BLOCK_SHIFT, or SB_SUPER_SHIFT for the coarse grid).
SB_INLINE float sbSkipTo(SB_GLOBAL const unsigned char* blockFlags, int shift, int resolution, float size,
                         float3 origin, float3 direction, float3 pos) {
  const float scale = (float)resolution / size;
  const float p[3] = {pos.x, pos.y, pos.z};
  const float o[3] = {origin.x, origin.y, origin.z};
  const float d[3] = {direction.x, direction.y, direction.z};
  const int blocksPerSide = resolution >> shift;
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    const int base = (int)sbFloor(p[a] * scale - 0.5f);
    lo[a] = sbClampInt(base, 0, resolution - 1) >> shift;
    hi[a] = sbClampInt(base + 1, 0, resolution - 1) >> shift;
  }
  for (int bz = lo[2]; bz <= hi[2]; ++bz)
    for (int by = lo[1]; by <= hi[1]; ++by)
      for (int bx = lo[0]; bx <= hi[0]; ++bx)
        if (blockFlags[bx + by * blocksPerSide + bz * blocksPerSide * blocksPerSide]) return -1.0f;
  // Interpolation cells stay inside blocks lo..hi while p*scale - 0.5 is in [lo*B, hi*B + B - 1).
  const float blockVoxels = (float)(1 << shift);
  float exitT = 1e30f;
  for (int a = 0; a < 3; ++a) {
    if (d[a] > 0.0f) exitT = sbFmin(exitT, ((((float)hi[a] + 1.0f) * blockVoxels - 0.5f) / scale - o[a]) / d[a]);
    if (d[a] < 0.0f) exitT = sbFmin(exitT, (((float)lo[a] * blockVoxels + 0.5f) / scale - o[a]) / d[a]);
  }
  return exitT;
}

// raycast: pixel (x, y) of an image with intrinsics k seen from `cameraToWorld`. The ray parameter t is the
// depth along the camera's z axis (metres), marched from nearPlane to farPlane (clipped to the volume) with
// `largeStep` until the tsdf falls below `smallStepBelow`, then with `smallStep`; the zero crossing is
// interpolated linearly. `blockFlags` and `superFlags` (see sbSkipTo; blocks of SB_BLOCK_SHIFT and
// SB_SUPER_SHIFT) may be 0: no empty-space skipping at that level. Writes the surface point and unit normal (volume frame) or vertex 0 and an invalid
// normal.
SB_INLINE void raycast(SB_GLOBAL sb_map_t* outVertex, SB_GLOBAL sb_map_t* outNormal, int width,
                       SB_GLOBAL const short* volume, int resolution, float size,
                       SB_GLOBAL const unsigned char* blockFlags, SB_GLOBAL const unsigned char* superFlags,
                       SbMat34 cameraToWorld, SbCamera k, float nearPlane,
                       float farPlane, float largeStep, float smallStep, float smallStepBelow, int x, int y) {
  const int index = y * width + x;
  const float3 origin = sbMakeFloat3(cameraToWorld.m[3], cameraToWorld.m[7], cameraToWorld.m[11]);
  const float3 direction = sbRotate(cameraToWorld, sbMakeFloat3(((float)x - k.cx) / k.fx, ((float)y - k.cy) / k.fy, 1.0f));
  // Entry and exit of the volume's box.
  float tEnter = nearPlane;
  float tExit = farPlane;
  const float o[3] = {origin.x, origin.y, origin.z};
  const float d[3] = {direction.x, direction.y, direction.z};
  for (int a = 0; a < 3; ++a) {
    if (d[a] != 0.0f) {
      const float t0 = (0.0f - o[a]) / d[a];
      const float t1 = (size - o[a]) / d[a];
      tEnter = sbFmax(tEnter, sbFmin(t0, t1));
      tExit = sbFmin(tExit, sbFmax(t0, t1));
    } else if (o[a] < 0.0f || o[a] > size) {
      tExit = -1.0f;
    }
  }
  float3 vertex = sbMakeFloat3(0.0f, 0.0f, 0.0f);
  float3 normal = sbMakeFloat3(SB_INVALID_NORMAL, 0.0f, 0.0f);
  if (tEnter < tExit) {
    float t = tEnter;
    float step = largeStep;
    float fPrevious = sbInterpolateTsdf(volume, resolution, size, origin + direction * t);
    float fCurrent = fPrevious;
    int first = 1;  // the first sample is at tEnter, already interpolated
    if (fPrevious > 0.0f) {
      for (; t < tExit; t += step) {
        const float3 pos = origin + direction * t;
        if (blockFlags != 0) {
          float skipTo = -1.0f;
          if (superFlags != 0) skipTo = sbSkipTo(superFlags, SB_SUPER_SHIFT, resolution, size, origin, direction, pos);
          if (skipTo <= t) skipTo = sbSkipTo(blockFlags, SB_BLOCK_SHIFT, resolution, size, origin, direction, pos);
          if (skipTo > t) {
            // The tsdf is +1 up to skipTo: continue just past it.
            t = sbFmax(t, skipTo + 1e-3f * smallStep - step);
            fPrevious = 1.0f;
            fCurrent = 1.0f;
            first = 0;
            continue;
          }
        }
        fCurrent = first ? fPrevious : sbInterpolateTsdf(volume, resolution, size, pos);
        first = 0;
        if (fCurrent < 0.0f) break;
        if (fCurrent < smallStepBelow) step = smallStep;
        fPrevious = fCurrent;
      }
      if (fCurrent < 0.0f) {
        t = t + step * fCurrent / (fPrevious - fCurrent);
        const float3 surface = origin + direction * t;
        const float3 g = sbTsdfGradient(volume, resolution, size, surface);
        const float len = sbLength(g);
        if (len > 0.0f) {
          vertex = surface;
          normal = g * (1.0f / len);
        }
      }
    }
  }
  SB_STORE_MAP3(vertex, outVertex, index);
  SB_STORE_MAP3(normal, outNormal, index);
}

// render: grey shading of raycast maps lit from `light` (volume frame, metres): 255 * clamp(ambient +
// max(0, n . l), 0, 1); pixels without a surface are 0. Writes one byte per pixel.
SB_INLINE void render(SB_GLOBAL unsigned char* out, SB_GLOBAL const sb_map_t* vertex, SB_GLOBAL const sb_map_t* normal,
                      int width, float3 light, float ambient, int x, int y) {
  const int index = y * width + x;
  const float3 n = SB_LOAD_MAP3(normal, index);
  float shade = 0.0f;
  if (n.x != SB_INVALID_NORMAL) {
    const float3 l = sbNormalize(light - SB_LOAD_MAP3(vertex, index));
    shade = sbClampFloat(ambient + sbFmax(0.0f, sbDot(n, l)), 0.0f, 1.0f);
  }
  out[index] = (unsigned char)(shade * 255.0f + 0.5f);
}
