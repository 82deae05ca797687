#include "pipeline/surface_blocks.h"

#include <algorithm>
#include <cmath>

namespace sb {

void SurfaceBlocks::markFrustum(int u0, int u1, int v0, int v1, float zNear, float zFar) {
  // Voxels of pixel u project into [u - 0.5, u + 0.5): the frustum's edges are the rays through the pixels'
  // outer corners, w(z) = t + z * d (volume frame) for the 4 corner directions d.
  const double xl = (u0 - 0.5 - k_.cx) / k_.fx, xh = (u1 + 0.5 - k_.cx) / k_.fx;
  const double yl = (v0 - 0.5 - k_.cy) / k_.fy, yh = (v1 + 0.5 - k_.cy) / k_.fy;
  const float* m = pose_.m;
  double dLo[3], dHi[3];  // per axis, the least and greatest component of the 4 directions
  for (int a = 0; a < 3; ++a) {
    dLo[a] = 1e30;
    dHi[a] = -1e30;
    for (int c = 0; c < 4; ++c) {
      const double d = m[4 * a] * ((c & 1) ? xh : xl) + m[4 * a + 1] * ((c & 2) ? yh : yl) + m[4 * a + 2];
      dLo[a] = std::min(dLo[a], d);
      dHi[a] = std::max(dHi[a], d);
    }
  }
  const double nearZ = std::max(double(zNear), 0.0);
  const double sliceM = 0.5 * voxel_ * (1 << kShift);
  const int slices = std::max(1, static_cast<int>(std::ceil((zFar - nearZ) / sliceM)));
  const int last = perSide_ * (1 << kShift) - 1;
  for (int s = 0; s < slices; ++s) {
    const double za = nearZ + (zFar - nearZ) * s / slices, zb = nearZ + (zFar - nearZ) * (s + 1) / slices;
    // Voxel i's centre is at (i + 0.5) * voxel: the voxels whose centre is in the slice's box, widened by the
    // margin (z >= 0: the box's extremes are at za or zb).
    int b0[3], b1[3];
    bool empty = false;
    for (int a = 0; a < 3; ++a) {
      const double lo = m[4 * a + 3] + std::min(za * dLo[a], zb * dLo[a]);
      const double hi = m[4 * a + 3] + std::max(za * dHi[a], zb * dHi[a]);
      const double i0 = std::ceil(lo / voxel_ - 0.5 - kMarginVoxels), i1 = std::floor(hi / voxel_ - 0.5 + kMarginVoxels);
      if (i1 < 0 || i0 > last || i0 > i1) {
        empty = true;
        break;
      }
      b0[a] = static_cast<int>(std::max(i0, 0.0)) >> kShift;
      b1[a] = static_cast<int>(std::min(i1, double(last))) >> kShift;
    }
    if (empty) continue;
    for (int bz = b0[2]; bz <= b1[2]; ++bz)
      for (int by = b0[1]; by <= b1[1]; ++by) {
        uint8_t* row = &marked_[static_cast<size_t>(perSide_) * (by + static_cast<size_t>(perSide_) * bz)];
        for (int bx = b0[0]; bx <= b1[0]; ++bx) row[bx] = 1;
      }
  }
}

void SurfaceBlocks::markTile(const float* depth, int width, int u0, int u1, int v0, int v1, float mu) {
  float dMin = INFINITY, dMax = 0.0f;
  for (int v = v0; v <= v1; ++v)
    for (int u = u0; u <= u1; ++u) {
      const float d = depth[static_cast<size_t>(v) * width + u];
      if (d > 0.0f) {
        dMin = std::min(dMin, d);
        dMax = std::max(dMax, d);
      }
    }
  if (!(dMax > 0.0f)) return;  // no reading in the tile
  if (dMax - dMin <= kTileRangeMu * mu || (u0 == u1 && v0 == v1)) {
    markFrustum(u0, u1, v0, v1, dMin - mu, dMax + mu);
    return;
  }
  // Readings too far apart for one frustum: the four quarters (a side of one pixel is not split).
  const int um = (u0 + u1) / 2, vm = (v0 + v1) / 2;
  markTile(depth, width, u0, um, v0, vm, mu);
  if (um < u1) markTile(depth, width, um + 1, u1, v0, vm, mu);
  if (vm < v1) markTile(depth, width, u0, um, vm + 1, v1, mu);
  if (um < u1 && vm < v1) markTile(depth, width, um + 1, u1, vm + 1, v1, mu);
}

void SurfaceBlocks::build(const float* depth, int width, int height, SbCamera k, SbMat34 cameraToVolume,
                          int resolution, float voxel, float mu, int tile) {
  perSide_ = resolution >> kShift;
  voxel_ = voxel;
  k_ = k;
  pose_ = cameraToVolume;
  const size_t blocks = static_cast<size_t>(perSide_) * perSide_ * perSide_;
  if (marked_.size() != blocks) {
    marked_.assign(blocks, 0);
  } else {
    for (const int32_t b : list_) marked_[static_cast<size_t>(b)] = 0;  // only what the last frame listed
  }
  list_.clear();
  tile = std::max(1, tile);
  for (int ty = 0; ty < height; ty += tile)
    for (int tx = 0; tx < width; tx += tile)
      markTile(depth, width, tx, std::min(width, tx + tile) - 1, ty, std::min(height, ty + tile) - 1, mu);
  for (size_t b = 0; b < blocks; ++b)
    if (marked_[b]) list_.push_back(static_cast<int32_t>(b));
}

}  // namespace sb
