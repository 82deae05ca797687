#pragma once
// The TSDF volume: resolution^3 voxels of side `size` metres; voxel (x, y, z) at index x + y*R + z*R*R holds
// two shorts (tsdf scaled so that SB_TSDF_SCALE means +1, weight). Voxel centres at ((x+0.5)*size/R, ...)
// in the volume (world) frame. Unobserved voxels hold (+1, 0).
//
// integrate: fusion of one depth image into the volume, one voxel per call.
//
// A moving volume (docs/moving-volume.md) is a cyclic buffer: the voxel at logical coordinates (x, y, z),
// counted from the volume's corner in the world, is stored at physical voxel ((x + o.x) mod R, (y + o.y) mod R,
// (z + o.z) mod R) for the offset o (SbVoxelOffset). Shifting the volume changes the offset and clears the slab
// that left; no voxel is copied. A fixed volume has offset 0: physical = logical. Every function below takes
// logical coordinates and reads through the offset; positions (metres) are in the volume frame, whose origin
// is the volume's corner.

#include "kernels/common.h"

#define SB_TSDF_SCALE 32767.0f
// Voxels closer to the camera plane than this (metres) are not projected.
#define SB_MIN_PROJECTION_DEPTH 0.0001f

// The cyclic buffer's offset, voxels per axis, each in [0, R).
typedef struct {
  int x, y, z;
} SbVoxelOffset;

// The physical coordinate of logical coordinate v in [0, R) on an axis of offset o in [0, R).
SB_INLINE int sbWrapVoxel(int v, int o, int resolution) {
  const int p = v + o;
  return p >= resolution ? p - resolution : p;
}

// The index (in voxels) of logical voxel (x, y, z), each in [0, R).
SB_INLINE int sbVoxelIndex(int resolution, SbVoxelOffset o, int x, int y, int z) {
  return sbWrapVoxel(x, o.x, resolution) +
         resolution * (sbWrapVoxel(y, o.y, resolution) + resolution * sbWrapVoxel(z, o.z, resolution));
}

// clearSlab: voxel (u, v, w) of the slab that leaves a moving volume, made unobserved (+1, 0): `count` physical
// planes normal to `axis` (0 x, 1 y, 2 z) from physical plane `first`, wrapping at R; u in [0, count) counts
// the planes, v and w in [0, R) the other two axes in order.
SB_INLINE void clearSlab(SB_GLOBAL short* volume, int resolution, int axis, int first, int u, int v, int w) {
  int p = first + u;
  if (p >= resolution) p -= resolution;
  const int x = axis == 0 ? p : v;
  const int y = axis == 1 ? p : (axis == 0 ? v : w);
  const int z = axis == 2 ? p : w;
  const int index = x + resolution * (y + resolution * z);
  volume[2 * index] = (short)SB_TSDF_SCALE;
  volume[2 * index + 1] = 0;
}

// Updates voxel `index` whose centre is `pos` in the camera frame (metres) with the depth image (metres,
// width x height, intrinsics k). mu: truncation distance (m).
SB_INLINE void integrateVoxel(SB_GLOBAL short* volume, int index, float3 pos, SB_GLOBAL const sb_map_t* depth,
                              int width, int height, SbCamera k, float mu, int maxWeight) {
  if (pos.z < SB_MIN_PROJECTION_DEPTH) return;
  const float invZ = 1.0f / pos.z;
  const float u = sbFloor(k.fx * pos.x * invZ + k.cx + 0.5f);
  const float v = sbFloor(k.fy * pos.y * invZ + k.cy + 0.5f);
  if (u < 0.0f || v < 0.0f || u > (float)(width - 1) || v > (float)(height - 1)) return;
  const float d = SB_LOAD_MAP(depth, (int)v * width + (int)u);
  if (d <= 0.0f) return;
  // Signed distance along the ray; the ray-length factor is >= 1, so a depth difference >= mu is free space
  // (sdf = +1) without computing it.
  const float alongZ = d - pos.z;
  float sdf = 1.0f;
  if (alongZ < mu) {
    const float qx = pos.x * invZ;
    const float qy = pos.y * invZ;
    const float diff = alongZ * sbSqrt(1.0f + qx * qx + qy * qy);
    if (diff <= -mu) return;
    sdf = sbFmin(1.0f, diff / mu);
  }
  const float oldTsdf = (float)volume[2 * index] / SB_TSDF_SCALE;
  const int oldWeight = volume[2 * index + 1];
  const float tsdf = sbClampFloat(((float)oldWeight * oldTsdf + sdf) / (float)(oldWeight + 1), -1.0f, 1.0f);
  const float scaled = tsdf * SB_TSDF_SCALE;
  const short stored = (short)(scaled >= 0.0f ? scaled + 0.5f : scaled - 0.5f);
  volume[2 * index] = stored;
  volume[2 * index + 1] = (short)(oldWeight + 1 < maxWeight ? oldWeight + 1 : maxWeight);
}

// integrate: logical voxel (x, y, z) with the volume-to-camera transform `worldToCamera` (the volume frame is
// the world frame for a volume that never moved).
SB_INLINE void integrate(SB_GLOBAL short* volume, int resolution, SbVoxelOffset offset, float size,
                         SbMat34 worldToCamera, SB_GLOBAL const sb_map_t* depth, int width, int height, SbCamera k,
                         float mu, int maxWeight, int x, int y, int z) {
  const float voxel = size / (float)resolution;
  const float3 centre = sbMakeFloat3(((float)x + 0.5f) * voxel, ((float)y + 0.5f) * voxel, ((float)z + 0.5f) * voxel);
  const int index = sbVoxelIndex(resolution, offset, x, y, z);
  integrateVoxel(volume, index, sbTransform(worldToCamera, centre), depth, width, height, k, mu, maxWeight);
}

// Trilinear interpolation of the tsdf at `s` in voxel coordinates (pos * resolution / size - 0.5: voxel
// centres at integers), clamped at the borders. Read through the cyclic offset: a cell across the physical
// wrap reads the same voxels as in a volume that never moved.
SB_INLINE float sbInterpolateTsdfVoxel(SB_GLOBAL const short* volume, int resolution, SbVoxelOffset o, float3 s) {
  const float sx = s.x, sy = s.y, sz = s.z;
  const int last = resolution - 1;
  const float lastF = (float)last;
  int x0, y0, z0, dx, dy, dz;
  float fx, fy, fz;
  if (sx >= 0.0f && sy >= 0.0f && sz >= 0.0f && sx < lastF && sy < lastF && sz < lastF) {
    // Inside: truncation is floor and all 8 corners exist.
    x0 = (int)sx;
    y0 = (int)sy;
    z0 = (int)sz;
    fx = sx - (float)x0;
    fy = sy - (float)y0;
    fz = sz - (float)z0;
    dx = 2;
    dy = 2 * resolution;
    dz = 2 * resolution * resolution;
  } else {
    const float bx = sbFloor(sx);
    const float by = sbFloor(sy);
    const float bz = sbFloor(sz);
    fx = sx - bx;
    fy = sy - by;
    fz = sz - bz;
    const int ix = (int)bx;
    const int iy = (int)by;
    const int iz = (int)bz;
    // Lower corner clamped into the volume; the step to the upper corner is 0 where it would leave it.
    x0 = sbClampInt(ix, 0, last);
    y0 = sbClampInt(iy, 0, last);
    z0 = sbClampInt(iz, 0, last);
    dx = (ix >= 0 && ix < last) ? 2 : 0;
    dy = (iy >= 0 && iy < last) ? 2 * resolution : 0;
    dz = (iz >= 0 && iz < last) ? 2 * resolution * resolution : 0;
  }
  // Physical corners: the step to the upper corner goes back by R - 1 voxels where the lower one is the
  // buffer's last (its upper neighbour is stored at 0).
  const int px = sbWrapVoxel(x0, o.x, resolution), py = sbWrapVoxel(y0, o.y, resolution),
            pz = sbWrapVoxel(z0, o.z, resolution);
  if (px == last) dx -= dx * resolution;
  if (py == last) dy -= dy * resolution;
  if (pz == last) dz -= dz * resolution;
  SB_GLOBAL const short* p = volume + 2 * (px + py * resolution + pz * resolution * resolution);
  const float c00 = (float)p[0] * (1.0f - fx) + (float)p[dx] * fx;
  const float c10 = (float)p[dy] * (1.0f - fx) + (float)p[dy + dx] * fx;
  const float c01 = (float)p[dz] * (1.0f - fx) + (float)p[dz + dx] * fx;
  const float c11 = (float)p[dz + dy] * (1.0f - fx) + (float)p[dz + dy + dx] * fx;
  const float c0 = c00 * (1.0f - fy) + c10 * fy;
  const float c1 = c01 * (1.0f - fy) + c11 * fy;
  return (c0 * (1.0f - fz) + c1 * fz) * (1.0f / SB_TSDF_SCALE);
}

// Gradient of the interpolated tsdf at voxel coordinates `s` (as sbInterpolateTsdfVoxel; unnormalised, in raw
// tsdf units per two voxels): on each axis the trilinear blend of the central differences v(i + 1) - v(i - 1)
// and v(i + 2) - v(i) around the interpolation cell's corners i, i + 1, indices clamped into the volume
// (SLAMBench KinectFusion's Volume::grad). 32 voxel reads, through the cyclic offset.
SB_INLINE float3 sbTsdfGradientVoxel(SB_GLOBAL const short* volume, int resolution, SbVoxelOffset o, float3 s) {
  const float bx = sbFloor(s.x);
  const float by = sbFloor(s.y);
  const float bz = sbFloor(s.z);
  const float fx = s.x - bx;
  const float fy = s.y - by;
  const float fz = s.z - bz;
  const int last = resolution - 1;
  const int ix = (int)bx;
  const int iy = (int)by;
  const int iz = (int)bz;
  // Offsets (in shorts) from voxel (x0, y0, z0) to i - 1, i + 1, i + 2 per axis; constant away from the
  // borders, clamped near them.
  const int sx = 2, sy = 2 * resolution, sz = 2 * resolution * resolution;
  // Physical coordinates of the clamped logical ones (sbWrapVoxel).
  const int x0 = sbWrapVoxel(sbClampInt(ix, 0, last), o.x, resolution);
  const int y0 = sbWrapVoxel(sbClampInt(iy, 0, last), o.y, resolution);
  const int z0 = sbWrapVoxel(sbClampInt(iz, 0, last), o.z, resolution);
  const int xm = (sbWrapVoxel(sbClampInt(ix - 1, 0, last), o.x, resolution) - x0) * sx,
            x1 = (sbWrapVoxel(sbClampInt(ix + 1, 0, last), o.x, resolution) - x0) * sx,
            x2 = (sbWrapVoxel(sbClampInt(ix + 2, 0, last), o.x, resolution) - x0) * sx;
  const int ym = (sbWrapVoxel(sbClampInt(iy - 1, 0, last), o.y, resolution) - y0) * sy,
            y1 = (sbWrapVoxel(sbClampInt(iy + 1, 0, last), o.y, resolution) - y0) * sy,
            y2 = (sbWrapVoxel(sbClampInt(iy + 2, 0, last), o.y, resolution) - y0) * sy;
  const int zm = (sbWrapVoxel(sbClampInt(iz - 1, 0, last), o.z, resolution) - z0) * sz,
            z1 = (sbWrapVoxel(sbClampInt(iz + 1, 0, last), o.z, resolution) - z0) * sz,
            z2 = (sbWrapVoxel(sbClampInt(iz + 2, 0, last), o.z, resolution) - z0) * sz;
  SB_GLOBAL const short* p = volume + 2 * (x0 + y0 * resolution + z0 * resolution * resolution);
  // The cell's corners c[z][y][x] (0: lower, 1: upper).
  const float c000 = (float)p[0], c001 = (float)p[x1];
  const float c010 = (float)p[y1], c011 = (float)p[y1 + x1];
  const float c100 = (float)p[z1], c101 = (float)p[z1 + x1];
  const float c110 = (float)p[z1 + y1], c111 = (float)p[z1 + y1 + x1];
  const float gx = (((c001 - (float)p[xm]) * (1.0f - fx) + ((float)p[x2] - c000) * fx) * (1.0f - fy) +
                    ((c011 - (float)p[y1 + xm]) * (1.0f - fx) + ((float)p[y1 + x2] - c010) * fx) * fy) *
                       (1.0f - fz) +
                   (((c101 - (float)p[z1 + xm]) * (1.0f - fx) + ((float)p[z1 + x2] - c100) * fx) * (1.0f - fy) +
                    ((c111 - (float)p[z1 + y1 + xm]) * (1.0f - fx) + ((float)p[z1 + y1 + x2] - c110) * fx) * fy) *
                       fz;
  const float gy = (((c010 - (float)p[ym]) * (1.0f - fy) + ((float)p[y2] - c000) * fy) * (1.0f - fx) +
                    ((c011 - (float)p[ym + x1]) * (1.0f - fy) + ((float)p[y2 + x1] - c001) * fy) * fx) *
                       (1.0f - fz) +
                   (((c110 - (float)p[z1 + ym]) * (1.0f - fy) + ((float)p[z1 + y2] - c100) * fy) * (1.0f - fx) +
                    ((c111 - (float)p[z1 + ym + x1]) * (1.0f - fy) + ((float)p[z1 + y2 + x1] - c101) * fy) * fx) *
                       fz;
  const float gz = (((c100 - (float)p[zm]) * (1.0f - fz) + ((float)p[z2] - c000) * fz) * (1.0f - fx) +
                    ((c101 - (float)p[zm + x1]) * (1.0f - fz) + ((float)p[z2 + x1] - c001) * fz) * fx) *
                       (1.0f - fy) +
                   (((c110 - (float)p[zm + y1]) * (1.0f - fz) + ((float)p[z2 + y1] - c010) * fz) * (1.0f - fx) +
                    ((c111 - (float)p[zm + y1 + x1]) * (1.0f - fz) + ((float)p[z2 + y1 + x1] - c011) * fz) * fx) *
                       fy;
  return sbMakeFloat3(gx, gy, gz);
}
