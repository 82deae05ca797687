#pragma once
// raycast: the model surface seen from a pose, one pixel per call (the reference for the next frame's ICP);
// render: a shaded image of raycast maps, for output only.

#include "kernels/volume.h"

// Samples of the march within this fraction of the small step before the end of a skipped box are still taken
// (the box's exit is computed in float; the interpolation is continuous, so this only costs a sample).
#define SB_SKIP_MARGIN 1e-3f

// Empty-space skipping, the one structure of both backends: a grid of blocks of (1 << SB_SKIP_SHIFT)^3
// voxels, 4^3, fine enough that the march enters few blocks with surface in front of the surface (measured
// on the CPU: fewer samples per ray than 8^3 blocks). Integration leaves a surface mask per block
// (sbBlockSurfaceMask); pipeline/block_distance.h turns the masks into the Chebyshev distance of every
// block to the nearest block with surface, which the march (sbSkipByDistance) jumps by.
#define SB_SKIP_SHIFT 2

// The ray bounds' tiles (pipeline/ray_bounds.h): SB_RAY_BOUNDS_TILE x SB_RAY_BOUNDS_TILE pixels.
#define SB_RAY_BOUNDS_TILE 8

// The surface mask bits that a voxel whose tsdf is below the small-step threshold sets in its block, from
// which of its block's lower faces it lies on: `faces` = (x % B == 0) + 2 (y % B == 0) + 4 (z % B == 0), B
// the block side. Bit c (c = cx + 2 cy + 4 cz) is set when c names only such axes (bit 0: any such voxel). A
// block b "has surface" for skipping when bit c of block b + c is set for some c: a voxel of b or of the
// first voxel layer of its upper neighbours (voxels B*b .. B*b + B per axis) is below the threshold.
SB_INLINE unsigned char sbSurfaceMaskBits(int faces) {
  unsigned char bits = 0;
  for (int c = 0; c < 8; ++c)
    if ((c & ~faces) == 0) bits = (unsigned char)(bits | (1u << c));
  return bits;
}

// The surface mask of block (bx, by, bz) of (1 << shift)^3 voxels: sbSurfaceMaskBits of every voxel of it
// whose stored tsdf is below `below` (raw units, pipeline/block_distance.h's surfaceTsdfBelow), or-ed. One
// block per call (the OpenCL backend's surfaceMaskKernel); the CPU backend or-s the same bits row by row
// inside its integrate, hand-vectorised (tests/pipeline/cpu/test_cpu_integrate.cpp checks its masks).
// Blocks are logical (the grid follows a moving volume); the voxels are read through the cyclic offset.
SB_INLINE unsigned char sbBlockSurfaceMask(SB_GLOBAL const short* volume, int resolution, SbVoxelOffset o, int shift,
                                           int below, int bx, int by, int bz) {
  const int side = 1 << shift;
  unsigned char mask = 0;
  for (int dz = 0; dz < side; ++dz)
    for (int dy = 0; dy < side; ++dy) {
      const int z = sbWrapVoxel((bz << shift) + dz, o.z, resolution), y = sbWrapVoxel((by << shift) + dy, o.y, resolution);
      SB_GLOBAL const short* row = volume + 2 * (y * resolution + z * resolution * resolution);
      const int rowFaces = (dy == 0 ? 2 : 0) + (dz == 0 ? 4 : 0);
      for (int dx = 0; dx < side; ++dx)
        if (row[2 * sbWrapVoxel((bx << shift) + dx, o.x, resolution)] < below)
          mask = (unsigned char)(mask | sbSurfaceMaskBits(rowFaces + (dx == 0 ? 1 : 0)));
    }
  return mask;
}

// Empty-space skipping by block distance: `blockDistance` holds one byte per block of (1 << shift)^3 voxels
// (blocksPerSide^3 blocks), the Chebyshev distance in blocks to the nearest block that has surface (see
// sbSurfaceMaskBits: a voxel of it or of the first voxel layer of its upper neighbours, voxels B*b .. B*b + B
// per axis with B = 1 << shift, stores a tsdf below the small-step threshold). `s` is the sample in voxel
// coordinates (the trilinear interpolation reads voxels floor(s) and floor(s) + 1 per axis), which the
// caller keeps in [0, R - 1) on every axis; the ray is s(t) = sOrigin + t * sDirection, sInverse its
// componentwise inverse (0 where the direction is 0: no skip then). With d >= 1 for the block b of floor(s),
// no block within d - 1 of b has surface, so while s stays in [B(b - d + 1), B(b + d)) on each axis the
// interpolation stays at or above the threshold: no sample there ends the march or changes its step.
// Returns the ray parameter where s leaves that box, or a value <= 0 when the block has surface.
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

// The march of one ray (see raycast), with empty-space skipping by `blockDistance` (blocks of
// (1 << distanceShift)^3 voxels) when it is not 0, else none. Samples are interpolated in voxel coordinates
// s(t) = sOrigin + t * sDirection.
SB_INLINE void sbRaycastPixel(SB_GLOBAL sb_map_t* outVertex, SB_GLOBAL sb_map_t* outNormal, int width,
                              SB_GLOBAL const short* volume, int resolution, SbVoxelOffset offset, float size,
                              SB_GLOBAL const unsigned char* blockDistance, int distanceShift,
                              SbMat34 cameraToWorld, SbCamera k, float nearPlane, float farPlane,
                              float largeStep, float smallStep, float smallStepBelow, float tMin, float tMax,
                              int x, int y) {
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
  // The ray bounds (pipeline/ray_bounds.h): no sample past tMax is below smallStepBelow, so none ends the march.
  tExit = sbFmin(tExit, tMax);
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
    int first = 1;            // the first sample is at tEnter, already interpolated
    int previousSkipped = 0;  // the sample before the current one was left out (fPrevious is not its value)
    float fPrevious = 1.0f;
    if (tMin > tEnter) {
      // No sample before tMin is below smallStepBelow (pipeline/ray_bounds.h): the march skips to it as it skips
      // a box, from the first sample (which is above 0, so the march starts).
      const int next = (int)sbFloor((tMin - SB_SKIP_MARGIN * smallStep - tBase) / step) + 1;
      n = next > 1 ? next : 1;
      first = 0;
      previousSkipped = 1;
      t = tBase + (float)n * step;
    } else {
      fPrevious = sbInterpolateTsdfVoxel(volume, resolution, offset, sOrigin + sDirection * t);
    }
    float fCurrent = fPrevious;
    if (fPrevious > 0.0f) {
      while (t < tExit) {
        const float3 s = sOrigin + sDirection * t;
        float skipTo = -1.0f;
        // Inside the small-step band (the previous sample was taken and is below smallStepBelow) the ray is at
        // a surface, where a skip is rarely found: no lookup there (not skipping is always exact).
        const int inBand = smallSteps && !previousSkipped && fPrevious < smallStepBelow;
        if (!inBand && blockDistance != 0 && t >= tLookupLo && t < tLookupHi)
          skipTo = sbSkipByDistance(blockDistance, blocksPerSide, distanceShift, s, sOrigin, sInverse);
        if (skipTo > t) {
          // Continue at the first grid sample past skipTo (less a rounding margin: a sample within it is
          // taken).
          const float skipEnd = sbFmin(skipTo, tExit) - SB_SKIP_MARGIN * smallStep;
          const int next = (int)sbFloor((skipEnd - tBase) / step) + 1;
          n = next > n + 1 ? next : n + 1;
          previousSkipped = 1;
          first = 0;
        } else {
          fCurrent = first ? fPrevious : sbInterpolateTsdfVoxel(volume, resolution, offset, s);
          first = 0;
          if (fCurrent < 0.0f) {
            if (previousSkipped)
              fPrevious = sbInterpolateTsdfVoxel(volume, resolution, offset,
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
        const float3 g = sbTsdfGradientVoxel(volume, resolution, offset, sOrigin + sDirection * t);
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
// interpolated linearly. `blockDistance`: the distance grid of blocks of (1 << SB_SKIP_SHIFT)^3 voxels (see
// sbSkipByDistance), or 0 for no empty-space skipping. `rayBounds`: per tile of SB_RAY_BOUNDS_TILE^2 pixels
// (`boundsColumns` tiles per row), tMin and tMax (pipeline/ray_bounds.h), or 0 for none. Skipping and the
// bounds leave the result unchanged (see sbRaycastPixel): only the number of samples differs. Writes the
// surface point and unit normal (volume frame) or vertex 0 and an invalid normal.
SB_INLINE void raycast(SB_GLOBAL sb_map_t* outVertex, SB_GLOBAL sb_map_t* outNormal, int width,
                       SB_GLOBAL const short* volume, int resolution, SbVoxelOffset offset, float size,
                       SB_GLOBAL const unsigned char* blockDistance, SB_GLOBAL const float* rayBounds,
                       int boundsColumns, SbMat34 cameraToWorld, SbCamera k, float nearPlane, float farPlane,
                       float largeStep, float smallStep, float smallStepBelow, int x, int y) {
  float tMin = -1e30f, tMax = 1e30f;
  if (rayBounds != 0) {
    const int tile = (y / SB_RAY_BOUNDS_TILE) * boundsColumns + x / SB_RAY_BOUNDS_TILE;
    tMin = rayBounds[2 * tile];
    tMax = rayBounds[2 * tile + 1];
  }
  sbRaycastPixel(outVertex, outNormal, width, volume, resolution, offset, size, blockDistance, SB_SKIP_SHIFT,
                 cameraToWorld, k, nearPlane, farPlane, largeStep, smallStep, smallStepBelow, tMin, tMax, x, y);
}

// The moving volume: moves pixel `index` of raycast maps from the frame of a volume whose corner lies at
// `corner` (world, metres) to the world frame. Pixels without a surface stay as they are. Only run for a
// volume that has moved, so a fixed volume's maps are untouched.
SB_INLINE void offsetVertex(SB_GLOBAL sb_map_t* vertex, SB_GLOBAL const sb_map_t* normal, float3 corner, int index) {
  if (SB_LOAD_MAP(normal, 3 * index) == SB_INVALID_NORMAL) return;
  SB_STORE_MAP3(SB_LOAD_MAP3(vertex, index) + corner, vertex, index);
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
