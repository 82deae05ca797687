#pragma once
// raycast: the model surface seen from a pose, one pixel per call (the reference for the next frame's ICP);
// render: a shaded image of raycast maps, for output only.

#include "kernels/volume.h"

// Samples of the march within this fraction of the small step before the end of a skipped box are still taken
// (the box's exit is computed in float; the interpolation is continuous, so this only costs a sample).
#define SB_SKIP_MARGIN 1e-3f

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

// Empty-space skipping by block distance (the CPU backend's structure): `blockDistance` holds one byte per
// block of (1 << shift)^3 voxels (blocksPerSide^3 blocks), the Chebyshev distance in blocks to the nearest
// block that has surface, where a block "has surface" when a voxel of it or of the first voxel layer of its
// upper neighbours (voxels B*b .. B*b + B per axis, B = 1 << shift) stores a tsdf below the small-step
// threshold. `s` is the sample in voxel coordinates (the trilinear interpolation reads voxels floor(s) and
// floor(s) + 1 per axis), which the caller keeps in [0, R - 1) on every axis; the ray is
// s(t) = sOrigin + t * sDirection, sInverse its componentwise inverse (0 where the direction is 0: no skip
// then). With d >= 1 for the block b of floor(s), no block within d - 1 of b has surface, so while s stays
// in [B(b - d + 1), B(b + d)) on each axis the interpolation stays at or above the threshold: no sample
// there ends the march or changes its step. Returns the ray parameter where s leaves that box, or a value
// <= 0 when the block has surface.
SB_INLINE float sbSkipByDistance(SB_GLOBAL const unsigned char* blockDistance, int blocksPerSide, int shift,
                                 float3 s, float3 sOrigin, float3 sInverse) {
  const int bx = (int)s.x >> shift;
  const int by = (int)s.y >> shift;
  const int bz = (int)s.z >> shift;
  const int d = blockDistance[bx + by * blocksPerSide + bz * blocksPerSide * blocksPerSide];
  if (d == 0) return -1.0f;
  const float blockVoxels = (float)(1 << shift);
  // The box face the ray leaves through on each axis (a select, not a branch).
  const float ex = (float)(sInverse.x >= 0.0f ? bx + d : bx - d + 1) * blockVoxels;
  const float ey = (float)(sInverse.y >= 0.0f ? by + d : by - d + 1) * blockVoxels;
  const float ez = (float)(sInverse.z >= 0.0f ? bz + d : bz - d + 1) * blockVoxels;
  return sbFmin((ex - sOrigin.x) * sInverse.x, sbFmin((ey - sOrigin.y) * sInverse.y, (ez - sOrigin.z) * sInverse.z));
}

// The ray-parameter interval [*lo, *hi) in which s(t) = sOrigin + t * sDirection stays inside [0, R - 1) on
// every axis with a margin of 1e-3 voxel (so that rounding in s(t) cannot leave it); *lo > *hi when empty.
SB_INLINE void sbVoxelRange(float3 sOrigin, float3 sDirection, int resolution, float* lo, float* hi) {
  const float margin = 1e-3f;
  const float top = (float)(resolution - 1) - margin;
  const float o[3] = {sOrigin.x, sOrigin.y, sOrigin.z};
  const float d[3] = {sDirection.x, sDirection.y, sDirection.z};
  float l = -1e30f, h = 1e30f;
  for (int a = 0; a < 3; ++a) {
    if (d[a] != 0.0f) {
      const float t0 = (margin - o[a]) / d[a];
      const float t1 = (top - o[a]) / d[a];
      l = sbFmax(l, sbFmin(t0, t1));
      h = sbFmin(h, sbFmax(t0, t1));
    } else if (!(o[a] >= margin && o[a] <= top)) {
      h = -1e30f;
    }
  }
  *lo = l;
  *hi = h;
}

// The march of one ray (see raycast), with empty-space skipping by `blockDistance` when it is not 0, else by
// `blockFlags` / `superFlags` when they are not 0, else none. Samples are interpolated in voxel coordinates
// s(t) = sOrigin + t * sDirection.
SB_INLINE void sbRaycastPixel(SB_GLOBAL sb_map_t* outVertex, SB_GLOBAL sb_map_t* outNormal, int width,
                              SB_GLOBAL const short* volume, int resolution, float size,
                              SB_GLOBAL const unsigned char* blockDistance, int distanceShift,
                              SB_GLOBAL const unsigned char* blockFlags,
                              SB_GLOBAL const unsigned char* superFlags, SbMat34 cameraToWorld, SbCamera k,
                              float nearPlane, float farPlane, float largeStep, float smallStep,
                              float smallStepBelow, int x, int y) {
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
  // The ray in voxel coordinates.
  const float scale = (float)resolution / size;
  const float3 sOrigin = origin * scale - sbMakeFloat3(0.5f, 0.5f, 0.5f);
  const float3 sDirection = direction * scale;
  const float3 sInverse = sbMakeFloat3(sDirection.x != 0.0f ? 1.0f / sDirection.x : 0.0f,
                                       sDirection.y != 0.0f ? 1.0f / sDirection.y : 0.0f,
                                       sDirection.z != 0.0f ? 1.0f / sDirection.z : 0.0f);
  // Where sbSkipByDistance may be asked (s inside [0, R - 1)).
  float tLookupLo, tLookupHi;
  sbVoxelRange(sOrigin, sDirection, resolution, &tLookupLo, &tLookupHi);
  const int blocksPerSide = resolution >> distanceShift;
  float3 vertex = sbMakeFloat3(0.0f, 0.0f, 0.0f);
  float3 normal = sbMakeFloat3(SB_INVALID_NORMAL, 0.0f, 0.0f);
  if (tEnter < tExit) {
    // Samples lie on a fixed grid, t = tBase + n * step: tEnter + n * largeStep, then from the first sample
    // below smallStepBelow on, that sample + n * smallStep. Skipping only leaves out samples of that grid
    // that lie where the interpolated tsdf is >= smallStepBelow (they would neither end the march nor change
    // the step), so the result does not depend on the skipping structure, nor on whether there is one.
    float tBase = tEnter;
    int n = 0;
    float step = largeStep;
    int smallSteps = 0;  // the step is smallStep
    float t = tEnter;
    float fPrevious = sbInterpolateTsdfVoxel(volume, resolution, sOrigin + sDirection * t);
    float fCurrent = fPrevious;
    int first = 1;            // the first sample is at tEnter, already interpolated
    int previousSkipped = 0;  // the sample before the current one was left out (fPrevious is not its value)
    if (fPrevious > 0.0f) {
      while (t < tExit) {
        const float3 s = sOrigin + sDirection * t;
        float skipTo = -1.0f;
        // Inside the small-step band (the previous sample was taken and is below smallStepBelow) the ray is at
        // a surface, where a skip is rarely found: no lookup there (not skipping is always exact).
        const int inBand = smallSteps && !previousSkipped && fPrevious < smallStepBelow;
        if (!inBand) {
          if (blockDistance != 0) {
            if (t >= tLookupLo && t < tLookupHi)
              skipTo = sbSkipByDistance(blockDistance, blocksPerSide, distanceShift, s, sOrigin, sInverse);
          } else if (blockFlags != 0) {
            const float3 pos = origin + direction * t;
            if (superFlags != 0)
              skipTo = sbSkipTo(superFlags, SB_SUPER_SHIFT, resolution, size, origin, direction, pos);
            if (skipTo <= t) skipTo = sbSkipTo(blockFlags, SB_BLOCK_SHIFT, resolution, size, origin, direction, pos);
          }
        }
        if (skipTo > t) {
          // Continue at the first grid sample past skipTo (less a rounding margin: a sample within it is
          // taken).
          const float skipEnd = sbFmin(skipTo, tExit) - SB_SKIP_MARGIN * smallStep;
          const int next = (int)sbFloor((skipEnd - tBase) / step) + 1;
          n = next > n + 1 ? next : n + 1;
          previousSkipped = 1;
          first = 0;
        } else {
          fCurrent = first ? fPrevious : sbInterpolateTsdfVoxel(volume, resolution, s);
          first = 0;
          if (fCurrent < 0.0f) {
            if (previousSkipped)
              fPrevious = sbInterpolateTsdfVoxel(volume, resolution,
                                                 sOrigin + sDirection * (tBase + (float)(n - 1) * step));
            break;
          }
          if (fCurrent < smallStepBelow && !smallSteps) {
            smallSteps = 1;
            step = smallStep;
            tBase = t;
            n = 0;
          }
          fPrevious = fCurrent;
          previousSkipped = 0;
          ++n;
        }
        t = tBase + (float)n * step;
      }
      if (fCurrent < 0.0f) {
        t = t + step * fCurrent / (fPrevious - fCurrent);
        const float3 g = sbTsdfGradientVoxel(volume, resolution, sOrigin + sDirection * t);
        const float len = sbLength(g);
        if (len > 0.0f) {
          vertex = origin + direction * t;
          normal = g * (1.0f / len);
        }
      }
    }
  }
  SB_STORE_MAP3(vertex, outVertex, index);
  SB_STORE_MAP3(normal, outNormal, index);
}

// raycast: pixel (x, y) of an image with intrinsics k seen from `cameraToWorld`. The ray parameter t is the
// depth along the camera's z axis (metres), marched from nearPlane to farPlane (clipped to the volume) with
// `largeStep` until the tsdf falls below `smallStepBelow`, then with `smallStep`; the zero crossing is
// interpolated linearly. `blockFlags` and `superFlags` (see sbSkipTo; blocks of SB_BLOCK_SHIFT and
// SB_SUPER_SHIFT) may be 0: no empty-space skipping at that level. Skipping leaves the result unchanged (see
// sbRaycastPixel): only the number of samples differs. Writes the surface point and unit normal
// (volume frame) or vertex 0 and an invalid normal.
SB_INLINE void raycast(SB_GLOBAL sb_map_t* outVertex, SB_GLOBAL sb_map_t* outNormal, int width,
                       SB_GLOBAL const short* volume, int resolution, float size,
                       SB_GLOBAL const unsigned char* blockFlags, SB_GLOBAL const unsigned char* superFlags,
                       SbMat34 cameraToWorld, SbCamera k, float nearPlane, float farPlane, float largeStep,
                       float smallStep, float smallStepBelow, int x, int y) {
  sbRaycastPixel(outVertex, outNormal, width, volume, resolution, size, 0, 0, blockFlags, superFlags,
                 cameraToWorld, k, nearPlane, farPlane, largeStep, smallStep, smallStepBelow, x, y);
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
