#pragma once
// Ray bounds of a raycast (issue 43), computed on the host by both backends from the empty-space skipping grid
// (pipeline/block_distance.h): per tile of kTile x kTile pixels of the raycast image, the camera depths
// [tMin, tMax] outside which no ray through the tile's pixels can take a sample below the small-step
// threshold. kernels/raycast.h starts each ray at the first sample of its grid at or before tMin and stops it
// past tMax: the samples it leaves out are exactly ones the march would have skipped or passed above the
// threshold, so the maps stay bit-identical; what changes is that a ray no longer walks the skipping grid from
// the near plane to the first surface, nor on to the far plane when there is none.
//
// A sample at s (voxel coordinates) reads only voxels of the skipping block of floor(s) and the first layer of
// its upper neighbours, which a block "with surface" (distance 0) covers; so such samples lie in the boxes of
// blocks of distance 0 (widened to the volume's faces for the border blocks, whose clamped interpolation reads
// them). The boxes are taken per group of kGroup^3 skipping blocks (kFineGroup^3 for large images; a group has
// surface when one of its blocks has), projected by their 8 corners (the projection of a box lies in the hull
// of its corners'), widened by kMarginVoxels; a box reaching behind kNearM of the camera plane bounds every
// tile from 0.

#include <vector>

#include "kernels/common.h"

namespace sb {

class RayBounds {
 public:
  static constexpr int kTile = 8;                // pixels per tile side
  // Skipping blocks per group side: kFineGroup for images of at least kFinePixels pixels, else kGroup. Finer
  // boxes bound the rays tighter (fewer lookups per ray) but cost more boxes to project, a cost that follows
  // the surface in view while the saving follows the pixels. Measured (issue 43, callgrind, instructions):
  // single blocks save 45 M of march per 640 x 480 raycast on 7-Scenes for 5 M more bounds; `adaptive` on
  // 7-Scenes (mostly 80 x 60) with single blocks at every size spends 0.74 G more on bounds over 600 frames
  // and saves 0.11 G of march.
  static constexpr int kGroup = 2;
  static constexpr int kFineGroup = 1;
  static constexpr int kFinePixels = 65536;
  static constexpr float kMarginVoxels = 0.1f;   // slack of the boxes for float rounding of the ray's samples
  static constexpr float kNearM = 0.01f;         // metres: boxes reaching closer to the camera plane bound all

  // The bounds of a width x height raycast with intrinsics k from `cameraToVolume`, for the block distances of
  // a resolution^3 volume of side `size` (metres) in blocks of (1 << shift)^3 voxels (perSide^3 of them).
  void compute(const unsigned char* blockDistance, int shift, int resolution, float size, SbMat34 cameraToVolume,
               SbCamera k, int width, int height);

  // Per tile (row-major, columns() per row): tMin, tMax (metres); tMin > tMax when no ray of it meets a surface.
  const std::vector<float>& bounds() const { return bounds_; }
  int columns() const { return columns_; }
  int rows() const { return rows_; }

 private:
  std::vector<float> bounds_;
  std::vector<unsigned char> groups_;  // per group: has surface
  std::vector<int> surface_;           // the groups with surface (x + groups * (y + groups * z))
  int columns_ = 0, rows_ = 0;
};

}  // namespace sb
