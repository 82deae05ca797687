#pragma once
// A TSDF volume filled from a signed distance function (positive in free space), for navmap's tests: every
// voxel in front of a surface or at most mu behind it is observed (weight 1), deeper ones are not.

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <functional>
#include <vector>

#include "navmap/voxel_votes.h"

namespace sb::navmap::test {

struct TsdfScene {
  int resolution = 200;
  double voxel = 0.02;  // metres: a 4 m cube
  double mu = 0.1;
  std::vector<int16_t> voxels;

  explicit TsdfScene(const std::function<double(const Eigen::Vector3d&)>& sdf, int r = 200, double v = 0.02)
      : resolution(r), voxel(v), voxels(2 * size_t(r) * r * r) {
    for (int z = 0; z < r; ++z)
      for (int y = 0; y < r; ++y)
        for (int x = 0; x < r; ++x) {
          const double d = sdf(Eigen::Vector3d(x + 0.5, y + 0.5, z + 0.5) * v);
          const size_t i = size_t(x) + size_t(r) * (size_t(y) + size_t(r) * size_t(z));
          voxels[2 * i] = int16_t(std::clamp(d / mu, -1.0, 1.0) * 32767.0);
          voxels[2 * i + 1] = d > -mu ? 1 : 0;
        }
  }
  VoxelBox box() const {
    VoxelBox b;
    b.data = voxels.data();
    b.dims = b.extent = {resolution, resolution, resolution};
    b.voxelSizeM = voxel;
    b.muM = mu;
    return b;
  }
};

}  // namespace sb::navmap::test
