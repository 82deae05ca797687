#pragma once
// Per-block carving (issue 43): which blocks of 8^3 voxels one integration visits when free space is carved
// block by block instead of over the whole view. Every integration visits the surface blocks (the band,
// pipeline/surface_blocks.h); a block in view (pipeline/integrate_cull.h: one whose voxels the
// integration may change) is visited whole, carving its free space, when it was never visited since it came
// into the volume (the volume's start, or a move of the moving volume that brought it in) or when it was last
// visited `every` or more integrations ago (this one counted). A visited block has all its voxels in view
// carved or fused, so its age starts again at 0; but a block never carved whole stays due while only part of
// it is in the image (integrate_cull.h's insideRow), so that the rest is carved as it comes into view (the
// cost: the never-carved blocks along the frustum's sides are visited every integration). Both backends
// integrate the list this makes (kernels/volume.h), so they carve the same voxels. every = 1 visits every
// block in view, every integration: KinectFusion's carving.
//
// The record is one byte per logical block (its age in integrations, saturating at kNever, which also means
// never visited); it follows the moving volume as the skipping grid does (shiftGrid), the blocks that come in
// starting at kNever. Cost per integration: one pass over the blocks (R^3 / 512 bytes) beside the cull.

#include <cstdint>
#include <vector>

#include "core/thread_pool.h"

namespace sb {

class IntegrateCull;
class SurfaceBlocks;

class CarveSchedule {
 public:
  static constexpr uint8_t kNever = 255;  // never visited since the block came into the volume
  static constexpr int kMaxEvery = 254;   // larger `every` values behave as this one

  // A volume of perSide^3 blocks, no block visited yet.
  void reset(int perSide);
  // The volume moved by `blocks` blocks along `axis` (0 x, 1 y, 2 z): block v now holds what block v + blocks
  // held, the blocks that came in were never visited.
  void shift(int axis, int blocks, ThreadPool& pool);
  // The blocks this integration visits, ascending (index bx + n * (by + n * bz)): those of `surface` and
  // those that `cull` keeps and that are due (never visited, or visited `every` or more integrations ago);
  // records the visit and ages the others by one integration. `surface` and `cull` must cover this volume.
  const std::vector<int32_t>& plan(const SurfaceBlocks& surface, const IntegrateCull& cull, int every);

  const std::vector<int32_t>& blocks() const { return list_; }
  // The blocks of the last plan that were listed for carving only (in view and due, not surface blocks).
  size_t carvedOnly() const { return carvedOnly_; }
  uint8_t age(int bx, int by, int bz) const {
    return age_[static_cast<size_t>(bx) +
                static_cast<size_t>(perSide_) * (by + static_cast<size_t>(perSide_) * bz)];
  }
  int perSide() const { return perSide_; }

 private:
  int perSide_ = 0;
  std::vector<uint8_t> age_;  // perSide^3: integrations since the last visit, kNever = none since it came in
  std::vector<int32_t> list_;
  size_t carvedOnly_ = 0;
};

}  // namespace sb
