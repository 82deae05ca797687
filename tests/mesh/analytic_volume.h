#pragma once
// Test helper: TSDF volumes filled analytically from a signed distance function, in the layout of
// sb::VolumeView (interleaved int16 tsdf/weight, tsdf scaled by 32767, voxel centres at (i + 0.5) * voxel).

#include "mesh/marching_cubes.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace sb::test {

struct AnalyticVolume {
  int resolution = 0;
  float size = 0.0f;            // metres
  std::vector<int16_t> data;    // 2 * resolution^3

  AnalyticVolume(int r, float sizeMeters)
      : resolution(r), size(sizeMeters), data(size_t(2) * size_t(r) * size_t(r) * size_t(r)) {
    for (size_t i = 0; i < data.size(); i += 2) {
      data[i] = static_cast<int16_t>(kTsdfScale);  // untouched: +1, weight 0
      data[i + 1] = 0;
    }
  }

  float voxel() const { return size / static_cast<float>(resolution); }
  size_t index(int x, int y, int z) const { return size_t(x) + size_t(resolution) * (size_t(y) + size_t(resolution) * size_t(z)); }
  Eigen::Vector3d centre(int x, int y, int z) const {
    return Eigen::Vector3d(x + 0.5, y + 0.5, z + 0.5) * double(voxel());
  }
  VolumeView view() const { return VolumeView{data.data(), resolution, size}; }

  // Stores clamp(sdf(p) / mu, -1, 1) with `weight` at every voxel for which `where(x, y, z)` holds.
  template <typename Sdf, typename Where>
  void fill(Sdf sdf, double muMeters, int16_t weight, Where where) {
    for (int z = 0; z < resolution; ++z)
      for (int y = 0; y < resolution; ++y)
        for (int x = 0; x < resolution; ++x) {
          if (!where(x, y, z)) continue;
          const double t = std::clamp(sdf(centre(x, y, z)) / muMeters, -1.0, 1.0);
          data[2 * index(x, y, z)] = static_cast<int16_t>(std::lround(t * kTsdfScale));
          data[2 * index(x, y, z) + 1] = weight;
        }
  }
  template <typename Sdf>
  void fill(Sdf sdf, double muMeters, int16_t weight) {
    fill(sdf, muMeters, weight, [](int, int, int) { return true; });
  }
};

}  // namespace sb::test
