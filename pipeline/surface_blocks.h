#pragma once
// The surface block list of one frame (issue 43): the blocks of 8^3 voxels that the truncation band of the
// frame's depth pixels crosses, the only blocks whose voxels integrate changes apart from free space (tsdf +1
// in front of the surface, which KinectFusion carves every frame and which pipeline/config.h's
// integrate_carve_every now bounds). Built on the host once per integration from the depth used at the
// frame's compute size, deduplicated through a bitmap, bounded by the number of blocks, and read by both
// backends' integrate (pipeline/cpu/, pipeline/opencl/) through kernels/volume.h's integrate.
//
// Exact for the band: a voxel whose update (kernels/volume.h, integrateVoxel) gives a tsdf below +1 projects
// (the floor of its projection plus half a pixel) onto a pixel u with a reading d and lies at camera depth z
// with |d - z| < mu; so its centre is inside the frustum of pixel u's square between depths d - mu and d + mu.
// Pixels are taken in tiles (tile x tile pixels): a tile whose readings span at most mu is one frustum from
// its nearest reading - mu to its farthest + mu, else its quarters are, down to single pixels. Each frustum is cut along the
// depth into slices no longer than half a block, and the blocks holding a voxel centre inside a slice's
// bounding box (widened by kMarginVoxels) are listed. Blocks are logical (a moving volume's blocks follow it;
// its cyclic offset is a multiple of 8 voxels, so a logical block is a contiguous block of the buffer).

#include <cstdint>
#include <vector>

#include "kernels/volume.h"

namespace sb {

class SurfaceBlocks {
 public:
  static constexpr int kShift = SB_SURFACE_BLOCK_SHIFT;  // blocks of (1 << kShift)^3 voxels
  static constexpr float kMarginVoxels = 0.05f;   // slack for float rounding of the kernel's voxel positions
  static constexpr float kTileRangeMu = 1.0f;     // a tile whose readings span more (in mu) is split in four

  // Lists the blocks of a resolution^3 volume of voxel side `voxel` (metres) that the band |d - z| < mu of the
  // depth image (metres, width x height, 0 = no reading; intrinsics k) crosses, seen from `cameraToVolume`
  // (the camera pose in the volume frame). `tile`: pixels per tile side (>= 1).
  void build(const float* depth, int width, int height, SbCamera k, SbMat34 cameraToVolume, int resolution, float voxel,
             float mu, int tile);

  // The listed blocks, ascending: index bx + n * (by + n * bz) with n = perSide().
  const std::vector<int32_t>& blocks() const { return list_; }
  int perSide() const { return perSide_; }
  bool contains(int bx, int by, int bz) const {
    return marked_[static_cast<size_t>(bx) + static_cast<size_t>(perSide_) * (by + static_cast<size_t>(perSide_) * bz)] != 0;
  }

 private:
  // Marks the frustum of pixels [u0, u1] x [v0, v1] from their nearest reading - mu to their farthest + mu, or
  // of each quarter when the readings span more than kTileRangeMu * mu.
  void markTile(const float* depth, int width, int u0, int u1, int v0, int v1, float mu);
  // Marks the blocks of the frustum of pixels [u0, u1] x [v0, v1] between camera depths zNear and zFar.
  void markFrustum(int u0, int u1, int v0, int v1, float zNear, float zFar);

  int perSide_ = 0;
  float voxel_ = 0.0f;
  SbCamera k_{};
  SbMat34 pose_{};
  std::vector<uint8_t> marked_;  // perSide^3, 1 = listed
  std::vector<int32_t> list_;
};

}  // namespace sb
