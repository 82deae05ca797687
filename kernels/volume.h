#pragma once
// The TSDF volume: resolution^3 voxels of side `size` metres; voxel (x, y, z) at index x + y*R + z*R*R holds
// two shorts (tsdf scaled so that SB_TSDF_SCALE means +1, weight). Voxel centres at ((x+0.5)*size/R, ...)
// in the volume (world) frame. Unobserved voxels hold (+1, 0).
//
// integrate: fusion of one depth image into the volume, one voxel per call.

#include "kernels/common.h"

#define SB_TSDF_SCALE 32767.0f
// Voxels closer to the camera plane than this (metres) are not projected.
#define SB_MIN_PROJECTION_DEPTH 0.0001f
// Blocks of the empty-space skipping grid are (1 << SB_BLOCK_SHIFT)^3 voxels.
#define SB_BLOCK_SHIFT 3
// Coarse skipping grid: (1 << SB_SUPER_SHIFT)^3 voxels per cell, used when the resolution is a multiple of it.
#define SB_SUPER_SHIFT 5

SB_INLINE float sbVoxelTsdf(SB_GLOBAL const short* volume, int resolution, int x, int y, int z) {
  return (float)volume[2 * (x + y * resolution + z * resolution * resolution)] * (1.0f / SB_TSDF_SCALE);
}

// Updates voxel `index` whose centre is `pos` in the camera frame (metres) with the depth image (metres,
// width x height, intrinsics k). mu: truncation distance (m). Returns 1 when the voxel now stores a tsdf below
// +1 (it is near a surface), else 0; the empty-space skipping grid is built from this.
SB_INLINE int integrateVoxel(SB_GLOBAL short* volume, int index, float3 pos, SB_GLOBAL const sb_map_t* depth,
                             int width, int height, SbCamera k, float mu, int maxWeight) {
  if (pos.z < SB_MIN_PROJECTION_DEPTH) return 0;
  const float invZ = 1.0f / pos.z;
  const float u = sbFloor(k.fx * pos.x * invZ + k.cx + 0.5f);
  const float v = sbFloor(k.fy * pos.y * invZ + k.cy + 0.5f);
  if (u < 0.0f || v < 0.0f || u > (float)(width - 1) || v > (float)(height - 1)) return 0;
  const float d = SB_LOAD_MAP(depth, (int)v * width + (int)u);
  if (d <= 0.0f) return 0;
  // Signed distance along the ray; the ray-length factor is >= 1, so a depth difference >= mu is free space
  // (sdf = +1) without computing it.
  const float alongZ = d - pos.z;
  float sdf = 1.0f;
  if (alongZ < mu) {
    const float qx = pos.x * invZ;
    const float qy = pos.y * invZ;
    const float diff = alongZ * sbSqrt(1.0f + qx * qx + qy * qy);
    if (diff <= -mu) return 0;
    sdf = sbFmin(1.0f, diff / mu);
  }
  const float oldTsdf = (float)volume[2 * index] / SB_TSDF_SCALE;
  const int oldWeight = volume[2 * index + 1];
  const float tsdf = sbClampFloat(((float)oldWeight * oldTsdf + sdf) / (float)(oldWeight + 1), -1.0f, 1.0f);
  const float scaled = tsdf * SB_TSDF_SCALE;
  const short stored = (short)(scaled >= 0.0f ? scaled + 0.5f : scaled - 0.5f);
  volume[2 * index] = stored;
  volume[2 * index + 1] = (short)(oldWeight + 1 < maxWeight ? oldWeight + 1 : maxWeight);
  return stored < (short)SB_TSDF_SCALE ? 1 : 0;
}

// integrate: voxel (x, y, z) with the world-to-camera transform `worldToCamera`.
SB_INLINE int integrate(SB_GLOBAL short* volume, int resolution, float size, SbMat34 worldToCamera,
                        SB_GLOBAL const sb_map_t* depth, int width, int height, SbCamera k, float mu, int maxWeight,
                        int x, int y, int z) {
  const float voxel = size / (float)resolution;
  const float3 centre = sbMakeFloat3(((float)x + 0.5f) * voxel, ((float)y + 0.5f) * voxel, ((float)z + 0.5f) * voxel);
  const int index = x + y * resolution + z * resolution * resolution;
  return integrateVoxel(volume, index, sbTransform(worldToCamera, centre), depth, width, height, k, mu, maxWeight);
}

// Trilinear interpolation of the tsdf at `pos` (volume frame, metres), clamped at the borders.
SB_INLINE float sbInterpolateTsdf(SB_GLOBAL const short* volume, int resolution, float size, float3 pos) {
  const float scale = (float)resolution / size;
  const float sx = pos.x * scale - 0.5f;
  const float sy = pos.y * scale - 0.5f;
  const float sz = pos.z * scale - 0.5f;
  const float bx = sbFloor(sx);
  const float by = sbFloor(sy);
  const float bz = sbFloor(sz);
  const float fx = sx - bx;
  const float fy = sy - by;
  const float fz = sz - bz;
  const int last = resolution - 1;
  const int ix = (int)bx;
  const int iy = (int)by;
  const int iz = (int)bz;
  // Lower corner clamped into the volume; the step to the upper corner is 0 where it would leave it.
  const int x0 = sbClampInt(ix, 0, last);
  const int y0 = sbClampInt(iy, 0, last);
  const int z0 = sbClampInt(iz, 0, last);
  const int dx = (ix >= 0 && ix < last) ? 2 : 0;
  const int dy = (iy >= 0 && iy < last) ? 2 * resolution : 0;
  const int dz = (iz >= 0 && iz < last) ? 2 * resolution * resolution : 0;
  SB_GLOBAL const short* p = volume + 2 * (x0 + y0 * resolution + z0 * resolution * resolution);
  const float c00 = (float)p[0] * (1.0f - fx) + (float)p[dx] * fx;
  const float c10 = (float)p[dy] * (1.0f - fx) + (float)p[dy + dx] * fx;
  const float c01 = (float)p[dz] * (1.0f - fx) + (float)p[dz + dx] * fx;
  const float c11 = (float)p[dz + dy] * (1.0f - fx) + (float)p[dz + dy + dx] * fx;
  const float c0 = c00 * (1.0f - fy) + c10 * fy;
  const float c1 = c01 * (1.0f - fy) + c11 * fy;
  return (c0 * (1.0f - fz) + c1 * fz) * (1.0f / SB_TSDF_SCALE);
}

// Gradient of the interpolated tsdf at `pos` by central differences one voxel apart (unnormalised).
SB_INLINE float3 sbTsdfGradient(SB_GLOBAL const short* volume, int resolution, float size, float3 pos) {
  const float h = size / (float)resolution;
  const float gx = sbInterpolateTsdf(volume, resolution, size, pos + sbMakeFloat3(h, 0.0f, 0.0f)) -
                   sbInterpolateTsdf(volume, resolution, size, pos - sbMakeFloat3(h, 0.0f, 0.0f));
  const float gy = sbInterpolateTsdf(volume, resolution, size, pos + sbMakeFloat3(0.0f, h, 0.0f)) -
                   sbInterpolateTsdf(volume, resolution, size, pos - sbMakeFloat3(0.0f, h, 0.0f));
  const float gz = sbInterpolateTsdf(volume, resolution, size, pos + sbMakeFloat3(0.0f, 0.0f, h)) -
                   sbInterpolateTsdf(volume, resolution, size, pos - sbMakeFloat3(0.0f, 0.0f, h));
  return sbMakeFloat3(gx, gy, gz);
}
