#include "pipeline/ray_bounds.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace sb {

void RayBounds::compute(const unsigned char* blockDistance, int shift, int resolution, float size,
                        SbMat34 cameraToVolume, SbCamera k, int width, int height) {
  columns_ = (width + kTile - 1) / kTile;
  rows_ = (height + kTile - 1) / kTile;
  const size_t tiles = static_cast<size_t>(columns_) * rows_;
  bounds_.assign(2 * tiles, 0.0f);
  for (size_t i = 0; i < tiles; ++i) {
    bounds_[2 * i] = INFINITY;
    bounds_[2 * i + 1] = -INFINITY;
  }
  const int blocks = resolution >> shift;
  const int group = width * height >= kFinePixels ? kFineGroup : kGroup;
  const int groups = (blocks + group - 1) / group;
  const size_t nb = static_cast<size_t>(blocks);
  // The groups with surface, listed once each (the bounds are minima and maxima: the order does not matter).
  // The blocks of distance 0 are few: the rows are scanned 8 distances at a time for a zero byte.
  groups_.assign(static_cast<size_t>(groups) * groups * groups, 0);
  surface_.clear();
  const auto add = [&](int x, int y, int z) {
    const int g = x / group + groups * (y / group + groups * (z / group));
    if (!groups_[static_cast<size_t>(g)]) {
      groups_[static_cast<size_t>(g)] = 1;
      surface_.push_back(g);
    }
  };
  constexpr uint64_t kOnes = 0x0101010101010101ull, kHighs = 0x8080808080808080ull;
  for (int z = 0; z < blocks; ++z)
    for (int y = 0; y < blocks; ++y) {
      const unsigned char* row = blockDistance + nb * (static_cast<size_t>(y) + nb * static_cast<size_t>(z));
      int x = 0;
      for (; x + 8 <= blocks; x += 8) {
        uint64_t word;
        std::memcpy(&word, row + x, sizeof word);
        if (((word - kOnes) & ~word & kHighs) == 0) continue;  // no zero byte among the 8
        for (int i = 0; i < 8; ++i)
          if (row[x + i] == 0) add(x + i, y, z);
      }
      for (; x < blocks; ++x)
        if (row[x] == 0) add(x, y, z);
    }
  // The volume frame to the camera's: the inverse of the rigid cameraToVolume (R^T (p - t)).
  const float* m = cameraToVolume.m;
  double r[3][3], t[3];
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) r[a][b] = m[4 * b + a];
    t[a] = -(m[3] * double(m[a]) + m[7] * double(m[4 + a]) + m[11] * double(m[8 + a]));
  }
  const double voxel = double(size) / resolution, margin = kMarginVoxels * voxel;
  const int side = group << shift;  // voxels per group side
  // The view's four side planes through the camera centre (camera frame, outward unit normals), a little
  // outside the pixel centres 0 .. width - 1 and 0 .. height - 1: a box wholly outside one of them, or wholly
  // behind kNearM, meets no ray of the image (with z > 0), so it is left out before its corners are projected
  // (a sphere around the box, the test per box; the corners' test below would leave it out or, for a box
  // reaching behind the near guard, bound every tile).
  const double slackPixels = 0.01;
  double planes[4][3];
  const double sides[4] = {(-slackPixels - k.cx) / k.fx, (width - 1 + slackPixels - k.cx) / k.fx,
                           (-slackPixels - k.cy) / k.fy, (height - 1 + slackPixels - k.cy) / k.fy};
  for (int i = 0; i < 4; ++i) {  // x < sides[0] z, x > sides[1] z, y < sides[2] z, y > sides[3] z
    const double sign = (i & 1) ? 1.0 : -1.0, norm = std::sqrt(1.0 + sides[i] * sides[i]);
    planes[i][0] = i < 2 ? sign / norm : 0.0;
    planes[i][1] = i < 2 ? 0.0 : sign / norm;
    planes[i][2] = -sign * sides[i] / norm;
  }
  bool everywhere = false;           // a box reaches behind the near guard: bounds every tile
  double allMin = INFINITY, allMax = -INFINITY;
  for (const int index : surface_) {
    const int gx = index % groups, gy = (index / groups) % groups, gz = index / (groups * groups);
    // Samples s in [side * g, side * (g + 1)) per axis, at positions (s + 0.5) * voxel; the border groups
    // reach the volume's faces.
    const int gi[3] = {gx, gy, gz};
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = gi[a] == 0 ? 0.0 : (side * gi[a] + 0.5) * voxel;
      hi[a] = (gi[a] + 1) * side >= resolution ? double(size) : (side * (gi[a] + 1) + 0.5) * voxel;
      lo[a] -= margin;
      hi[a] += margin;
    }
    double centre[3], radius2 = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double c = 0.5 * (lo[a] + hi[a]), h = 0.5 * (hi[a] - lo[a]);
      centre[a] = c;
      radius2 += h * h;
    }
    const double radius = std::sqrt(radius2) * (1.0 + 1e-9);
    double cq[3];
    for (int a = 0; a < 3; ++a) cq[a] = r[a][0] * centre[0] + r[a][1] * centre[1] + r[a][2] * centre[2] + t[a];
    if (cq[2] + radius < kNearM) continue;
    bool outside = false;
    for (int i = 0; i < 4 && !outside; ++i)
      outside = planes[i][0] * cq[0] + planes[i][1] * cq[1] + planes[i][2] * cq[2] > radius;
    if (outside) continue;
    double zMin = INFINITY, zMax = -INFINITY, uMin = INFINITY, uMax = -INFINITY, vMin = INFINITY, vMax = -INFINITY;
    for (int c = 0; c < 8; ++c) {
      const double p[3] = {(c & 1) ? hi[0] : lo[0], (c & 2) ? hi[1] : lo[1], (c & 4) ? hi[2] : lo[2]};
      double q[3];
      for (int a = 0; a < 3; ++a) q[a] = r[a][0] * p[0] + r[a][1] * p[1] + r[a][2] * p[2] + t[a];
      zMin = std::min(zMin, q[2]);
      zMax = std::max(zMax, q[2]);
      if (q[2] >= kNearM) {
        uMin = std::min(uMin, k.fx * q[0] / q[2] + k.cx);
        uMax = std::max(uMax, k.fx * q[0] / q[2] + k.cx);
        vMin = std::min(vMin, k.fy * q[1] / q[2] + k.cy);
        vMax = std::max(vMax, k.fy * q[1] / q[2] + k.cy);
      }
    }
    if (zMax < kNearM) continue;  // wholly behind the camera plane: no ray (t > 0) meets it
    if (zMin < kNearM) {
      everywhere = true;
      allMin = std::min(allMin, zMin);
      allMax = std::max(allMax, zMax);
      continue;
    }
    // Pixel x's ray (direction ((x - cx) / fx, (y - cy) / fy, 1)) meets the box only if x is in [uMin, uMax].
    const double x0 = std::ceil(uMin - 1e-3), x1 = std::floor(uMax + 1e-3);
    const double y0 = std::ceil(vMin - 1e-3), y1 = std::floor(vMax + 1e-3);
    if (x1 < 0 || y1 < 0 || x0 > width - 1 || y0 > height - 1 || x0 > x1 || y0 > y1) continue;
    const int c0 = static_cast<int>(std::max(x0, 0.0)) / kTile, c1 = static_cast<int>(std::min(x1, width - 1.0)) / kTile;
    const int r0 = static_cast<int>(std::max(y0, 0.0)) / kTile, r1 = static_cast<int>(std::min(y1, height - 1.0)) / kTile;
    const float tMin = static_cast<float>(zMin), tMax = static_cast<float>(zMax);
    for (int row = r0; row <= r1; ++row)
      for (int col = c0; col <= c1; ++col) {
        float* b = &bounds_[2 * (static_cast<size_t>(row) * columns_ + col)];
        b[0] = std::min(b[0], tMin);
        b[1] = std::max(b[1], tMax);
      }
  }
  if (everywhere)
    for (size_t i = 0; i < tiles; ++i) {
      bounds_[2 * i] = std::min(bounds_[2 * i], static_cast<float>(std::max(allMin, 0.0)));
      bounds_[2 * i + 1] = std::max(bounds_[2 * i + 1], static_cast<float>(allMax));
    }
}

}  // namespace sb
