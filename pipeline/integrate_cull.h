#pragma once
// Block culling for the CPU backend's integrate: which blocks of 8^3 voxels one integration cannot change,
// decided from the block's corners and a max-depth pyramid of the depth image, so that integrate visits only
// the others. Exact: a
// block is culled only when every voxel in it would leave integrateVoxel() without an update, because
//   - no voxel of it projects into the image, or
//   - every pixel its voxels can project to has no reading (depth 0), or
//   - every voxel lies at least mu behind the farthest reading in that footprint (d - z <= -mu, the kernel's
//     "behind the surface" return).
// Bounds are conservative: the footprint is the box of the projected block corners (the voxel centres are
// inside the corners' convex hull, and a perspective projection keeps it convex) widened by kMarginPx pixels,
// the depth bound is the max over pyramid tiles covering it, and the depth test keeps kMarginM of slack for
// the float rounding of the kernel's voxel positions. Blocks with a corner closer than kNearGuardM to the
// camera plane are never culled.

#include <cstdint>
#include <vector>

#include "core/thread_pool.h"
#include "kernels/common.h"

namespace sb {

class IntegrateCull {
 public:
  static constexpr int kShift = 3;            // blocks of (1 << kShift)^3 voxels
  static constexpr double kMarginPx = 2.0;    // footprint slack, pixels
  static constexpr double kMarginM = 1e-3;    // depth slack, metres
  static constexpr double kNearGuardM = 0.1;  // closer corners: the block is kept

  // Decides every block of a resolution^3 volume (resolution a multiple of 8) of voxel side `voxel` for the
  // depth image (metres, width x height, 0 = no reading) seen through `k` with `worldToCamera`.
  void update(ThreadPool& pool, const float* depth, int width, int height, SbCamera k, SbMat34 worldToCamera,
              int resolution, float voxel, float mu);

  int blocks() const { return blocks_; }
  // 1 where block (bx, by, bz) may change, 0 where it is culled; the blocks of one row of blocks
  // (bx = 0 .. blocks() - 1) are contiguous.
  const uint8_t* liveRow(int by, int bz) const {
    return &live_[(static_cast<size_t>(bz) * blocks_ + static_cast<size_t>(by)) * blocks_];
  }
  bool anyLive(int by, int bz) const { return rowLive_[static_cast<size_t>(bz) * blocks_ + by] != 0; }
  // Blocks culled by the last update (for tests and counters).
  size_t culledCount() const;
  size_t liveCount() const { return live_.size() - culledCount(); }

 private:
  struct Corner {
    double x, y, z;  // camera frame (m)
    double u, v;     // projection (pixels, before the floor), valid when z >= guard
  };
  void buildPyramid(const float* depth, int width, int height);
  // Max reading over pixels [u0, u1] x [v0, v1] (inclusive, inside the image) or a superset of them.
  float maxDepth(int u0, int u1, int v0, int v1) const;

  int blocks_ = 0;
  std::vector<Corner> corners_;     // (blocks + 1)^3 grid of block corners
  std::vector<uint8_t> live_;       // blocks^3
  std::vector<uint8_t> rowLive_;    // blocks^2: 1 where a row of blocks (by, bz) has a live block
  std::vector<std::vector<float>> pyramid_;  // level L: max reading per tile of (8 << L)^2 pixels (0: none)
  std::vector<int> pyramidCols_, pyramidRows_;
};

}  // namespace sb
