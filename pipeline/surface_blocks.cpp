#include "pipeline/surface_blocks.h"

#include <algorithm>
#include <cmath>

namespace sb {

void SurfaceBlocks::markFrustum(int u0, int u1, int v0, int v1, float zNear, float zFar) {
  // Voxels of pixel u project into [u - 0.5, u + 0.5): the frustum's rays at the pixels' outer edges.
  const double xl = (u0 - 0.5 - k_.cx) / k_.fx, xh = (u1 + 0.5 - k_.cx) / k_.fx;
  const double yl = (v0 - 0.5 - k_.cy) / k_.fy, yh = (v1 + 0.5 - k_.cy) / k_.fy;
  const double nearZ = std::max(double(zNear), 0.0);
  const double sliceM = 0.5 * voxel_ * (1 << kShift);
  const int slices = std::max(1, static_cast<int>(std::ceil((zFar - nearZ) / sliceM)));
  const float* m = pose_.m;
  const int last = perSide_ * (1 << kShift) - 1;
  for (int s = 0; s < slices; ++s) {
    const double za = nearZ + (zFar - nearZ) * s / slices, zb = nearZ + (zFar - nearZ) * (s + 1) / slices;
    double lo[3] = {1e30, 1e30, 1e30}, hi[3] = {-1e30, -1e30, -1e30};
    for (int c = 0; c < 8; ++c) {
      const double z = (c & 4) ? zb : za;
      const double p[3] = {((c & 1) ? xh : xl) * z, ((c & 2) ? yh : yl) * z, z};
      for (int a = 0; a < 3; ++a) {
        const double w = m[4 * a] * p[0] + m[4 * a + 1] * p[1] + m[4 * a + 2] * p[2] + m[4 * a + 3];
        lo[a] = std::min(lo[a], w);
        hi[a] = std::max(hi[a], w);
      }
    }
    // Voxel i's centre is at (i + 0.5) * voxel: the voxels whose centre is in [lo, hi], widened by the margin.
    int b0[3], b1[3];
    bool empty = false;
    for (int a = 0; a < 3; ++a) {
      const double i0 = std::ceil(lo[a] / voxel_ - 0.5 - kMarginVoxels), i1 = std::floor(hi[a] / voxel_ - 0.5 + kMarginVoxels);
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
    for (int tx = 0; tx < width; tx += tile) {
      const int u1 = std::min(width, tx + tile) - 1, v1 = std::min(height, ty + tile) - 1;
      float dMin = INFINITY, dMax = 0.0f;
      for (int v = ty; v <= v1; ++v)
        for (int u = tx; u <= u1; ++u) {
          const float d = depth[static_cast<size_t>(v) * width + u];
          if (d > 0.0f) {
            dMin = std::min(dMin, d);
            dMax = std::max(dMax, d);
          }
        }
      if (!(dMax > 0.0f)) continue;  // no reading in the tile
      if (dMax - dMin <= mu) {
        markFrustum(tx, u1, ty, v1, dMin - mu, dMax + mu);
        continue;
      }
      for (int v = ty; v <= v1; ++v)
        for (int u = tx; u <= u1; ++u) {
          const float d = depth[static_cast<size_t>(v) * width + u];
          if (d > 0.0f) markFrustum(u, u, v, v, d - mu, d + mu);
        }
    }
  for (size_t b = 0; b < blocks; ++b)
    if (marked_[b]) list_.push_back(static_cast<int32_t>(b));
}

}  // namespace sb
