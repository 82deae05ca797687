#include "pipeline/integrate_cull.h"

#include <algorithm>
#include <cmath>

#include "kernels/volume.h"

namespace sb {

namespace {

constexpr int kBaseTileShift = 3;  // pyramid level 0: tiles of 8 x 8 pixels
constexpr int kLevels = 5;         // up to 128 x 128 pixel tiles
constexpr int kMaxTilesPerSide = 4;  // a query picks the finest level where the footprint spans this many

}  // namespace

void IntegrateCull::buildPyramid(const float* depth, int width, int height) {
  pyramid_.resize(kLevels);
  pyramidCols_.resize(kLevels);
  pyramidRows_.resize(kLevels);
  for (int level = 0; level < kLevels; ++level) {
    const int shift = kBaseTileShift + level;
    const int cols = ((width - 1) >> shift) + 1, rows = ((height - 1) >> shift) + 1;
    pyramidCols_[level] = cols;
    pyramidRows_[level] = rows;
    std::vector<float>& tiles = pyramid_[level];
    tiles.assign(static_cast<size_t>(cols) * rows, 0.0f);
    if (level == 0) {
      for (int y = 0; y < height; ++y) {
        float* tileRow = &tiles[static_cast<size_t>(y >> shift) * cols];
        const float* row = depth + static_cast<size_t>(y) * width;
        for (int x = 0; x < width; ++x) tileRow[x >> shift] = std::max(tileRow[x >> shift], row[x]);
      }
    } else {
      const std::vector<float>& finer = pyramid_[level - 1];
      const int finerCols = pyramidCols_[level - 1], finerRows = pyramidRows_[level - 1];
      for (int y = 0; y < finerRows; ++y)
        for (int x = 0; x < finerCols; ++x) {
          float& tile = tiles[static_cast<size_t>(y >> 1) * cols + (x >> 1)];
          tile = std::max(tile, finer[static_cast<size_t>(y) * finerCols + x]);
        }
    }
  }
}

float IntegrateCull::maxDepth(int u0, int u1, int v0, int v1) const {
  int level = 0;
  while (level + 1 < kLevels && (((u1 >> (kBaseTileShift + level)) - (u0 >> (kBaseTileShift + level)) >= kMaxTilesPerSide) ||
                                 ((v1 >> (kBaseTileShift + level)) - (v0 >> (kBaseTileShift + level)) >= kMaxTilesPerSide)))
    ++level;
  const int shift = kBaseTileShift + level;
  const int cols = pyramidCols_[level];
  const std::vector<float>& tiles = pyramid_[level];
  float best = 0.0f;
  for (int ty = v0 >> shift; ty <= v1 >> shift; ++ty)
    for (int tx = u0 >> shift; tx <= u1 >> shift; ++tx) best = std::max(best, tiles[static_cast<size_t>(ty) * cols + tx]);
  return best;
}

void IntegrateCull::update(ThreadPool& pool, const float* depth, int width, int height, SbCamera k,
                           SbMat34 worldToCamera, int resolution, float voxel, float mu) {
  blocks_ = resolution >> kShift;
  const int side = 1 << kShift;
  const int points = blocks_ + 1;
  corners_.resize(static_cast<size_t>(points) * points * points);
  live_.resize(static_cast<size_t>(blocks_) * blocks_ * blocks_);
  rowLive_.resize(static_cast<size_t>(blocks_) * blocks_);
  buildPyramid(depth, width, height);
  const float* m = worldToCamera.m;
  // Corner grid: block b spans voxel centres (b * side + 0.5 .. b * side + side - 0.5) * voxel per axis, inside
  // [g(b), g(b + 1)] with g(b) = (b * side + 0.5) * voxel.
  pool.parallelFor(0, points, 1, [&](int, int z0, int z1) {
    for (int zi = z0; zi < z1; ++zi)
      for (int yi = 0; yi < points; ++yi)
        for (int xi = 0; xi < points; ++xi) {
          const double x = (xi * side + 0.5) * voxel, y = (yi * side + 0.5) * voxel, z = (zi * side + 0.5) * voxel;
          const double cx = double(m[0]) * x + double(m[1]) * y + double(m[2]) * z + double(m[3]);
          const double cy = double(m[4]) * x + double(m[5]) * y + double(m[6]) * z + double(m[7]);
          const double cz = double(m[8]) * x + double(m[9]) * y + double(m[10]) * z + double(m[11]);
          Corner& c = corners_[(static_cast<size_t>(zi) * points + yi) * points + xi];
          c.x = cx;
          c.y = cy;
          c.z = cz;
          if (cz >= kNearGuardM) {
            c.u = k.fx * cx / cz + k.cx + 0.5;
            c.v = k.fy * cy / cz + k.cy + 0.5;
          }
        }
  });
  pool.parallelFor(0, blocks_, 1, [&](int, int bz0, int bz1) {
    for (int bz = bz0; bz < bz1; ++bz)
      for (int by = 0; by < blocks_; ++by)
        for (int bx = 0; bx < blocks_; ++bx) {
          const size_t b = (static_cast<size_t>(bz) * blocks_ + by) * blocks_ + bx;
          uint8_t& live = live_[b];
          live = 1;
          double zMin = INFINITY, uMin = INFINITY, uMax = -INFINITY, vMin = INFINITY, vMax = -INFINITY;
          for (int corner = 0; corner < 8; ++corner) {
            const Corner& c = corners_[(static_cast<size_t>(bz + (corner >> 2)) * points + by + ((corner >> 1) & 1)) *
                                           points + bx + (corner & 1)];
            zMin = std::min(zMin, c.z);
            if (c.z < kNearGuardM) break;
            uMin = std::min(uMin, c.u);
            uMax = std::max(uMax, c.u);
            vMin = std::min(vMin, c.v);
            vMax = std::max(vMax, c.v);
          }
          if (zMin < kNearGuardM) continue;
          // Pixels the voxels can land on (the kernel takes the floor of the projection).
          const double u0 = std::floor(uMin - kMarginPx), u1 = std::floor(uMax + kMarginPx);
          const double v0 = std::floor(vMin - kMarginPx), v1 = std::floor(vMax + kMarginPx);
          if (u1 < 0 || v1 < 0 || u0 > width - 1 || v0 > height - 1) {
            live = 0;  // outside the image
            continue;
          }
          const float farthest = maxDepth(static_cast<int>(std::max(u0, 0.0)), static_cast<int>(std::min(u1, width - 1.0)),
                                          static_cast<int>(std::max(v0, 0.0)), static_cast<int>(std::min(v1, height - 1.0)));
          if (farthest <= 0.0f || zMin >= double(farthest) + double(mu) + kMarginM) live = 0;
        }
    for (int bz = bz0; bz < bz1; ++bz)
      for (int by = 0; by < blocks_; ++by) {
        const uint8_t* row = &live_[(static_cast<size_t>(bz) * blocks_ + by) * blocks_];
        rowLive_[static_cast<size_t>(bz) * blocks_ + by] = std::find(row, row + blocks_, 1) != row + blocks_;
      }
  });
}

size_t IntegrateCull::culledCount() const { return static_cast<size_t>(std::count(live_.begin(), live_.end(), 0)); }

}  // namespace sb
