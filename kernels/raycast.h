#pragma once
// raycast: the model surface seen from a pose, one pixel per call (the reference for the next frame's ICP);
// render: a shaded image of raycast maps, for output only.

#include "kernels/volume.h"

// Empty-space skipping grid: one byte per block of (1 << SB_BLOCK_SHIFT)^3 voxels, non-zero when the block
// and its 26 neighbours hold no tsdf below +1, so that every interpolation inside it returns exactly +1 and
// the ray may jump to the block's exit. `skip` may be 0 (no skipping).
SB_INLINE int sbSkippable(SB_GLOBAL const unsigned char* skip, int blocksPerSide, float blockSize, float3 pos) {
  const int bx = (int)sbFloor(pos.x / blockSize);
  const int by = (int)sbFloor(pos.y / blockSize);
  const int bz = (int)sbFloor(pos.z / blockSize);
  if (bx < 0 || by < 0 || bz < 0 || bx >= blocksPerSide || by >= blocksPerSide || bz >= blocksPerSide) return 0;
  return skip[bx + by * blocksPerSide + bz * blocksPerSide * blocksPerSide];
}

// Ray parameter where the ray leaves the block that contains `pos`.
SB_INLINE float sbBlockExit(float3 origin, float3 direction, float blockSize, float3 pos) {
  float exitT = 1e30f;
  const float b[3] = {sbFloor(pos.x / blockSize), sbFloor(pos.y / blockSize), sbFloor(pos.z / blockSize)};
  const float o[3] = {origin.x, origin.y, origin.z};
  const float d[3] = {direction.x, direction.y, direction.z};
  for (int a = 0; a < 3; ++a) {
    if (d[a] > 0.0f) exitT = sbFmin(exitT, ((b[a] + 1.0f) * blockSize - o[a]) / d[a]);
    if (d[a] < 0.0f) exitT = sbFmin(exitT, (b[a] * blockSize - o[a]) / d[a]);
  }
  return exitT;
}

// raycast: pixel (x, y) of an image with intrinsics k seen from `cameraToWorld`. The ray parameter t is the
// depth along the camera's z axis (metres), marched from nearPlane to farPlane (clipped to the volume) with
// `largeStep` until the tsdf falls below `smallStepBelow`, then with `smallStep`; the zero crossing is
// interpolated linearly. Writes the surface point and unit normal (volume frame) or vertex 0 and an invalid
// normal.
SB_INLINE void raycast(SB_GLOBAL sb_map_t* outVertex, SB_GLOBAL sb_map_t* outNormal, int width,
                       SB_GLOBAL const short* volume, int resolution, float size,
                       SB_GLOBAL const unsigned char* skip, SbMat34 cameraToWorld, SbCamera k, float nearPlane,
                       float farPlane, float largeStep, float smallStep, float smallStepBelow, int x, int y) {
  const int index = y * width + x;
  const float3 origin = sbMakeFloat3(cameraToWorld.m[3], cameraToWorld.m[7], cameraToWorld.m[11]);
  const float3 direction = sbRotate(cameraToWorld, sbMakeFloat3(((float)x - k.cx) / k.fx, ((float)y - k.cy) / k.fy, 1.0f));
  const int blocksPerSide = resolution >> SB_BLOCK_SHIFT;
  const float blockSize = size / (float)blocksPerSide;
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
    if (fPrevious > 0.0f) {
      for (; t < tExit; t += step) {
        const float3 pos = origin + direction * t;
        if (skip != 0 && sbSkippable(skip, blocksPerSide, blockSize, pos)) {
          // Everything interpolated in this block is +1: continue just past its exit.
          const float jump = sbBlockExit(origin, direction, blockSize, pos) + 1e-4f * smallStep;
          t = sbFmax(t, jump - step);
          fPrevious = 1.0f;
          fCurrent = 1.0f;
          continue;
        }
        fCurrent = sbInterpolateTsdf(volume, resolution, size, pos);
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
