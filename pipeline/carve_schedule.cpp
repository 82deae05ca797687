#include "pipeline/carve_schedule.h"

#include <algorithm>

#include "core/error.h"
#include "pipeline/integrate_cull.h"
#include "pipeline/surface_blocks.h"
#include "pipeline/volume_placement.h"

namespace sb {

void CarveSchedule::reset(int perSide) {
  perSide_ = perSide;
  age_.assign(static_cast<size_t>(perSide) * perSide * perSide, kNever);
  list_.clear();
  list_.reserve(age_.size());
  carvedOnly_ = 0;
}

void CarveSchedule::shift(int axis, int blocks, ThreadPool& pool) {
  if (blocks != 0) shiftGrid(age_.data(), perSide_, axis, blocks, kNever, pool);
}

const std::vector<int32_t>& CarveSchedule::plan(const SurfaceBlocks& surface, const IntegrateCull& cull,
                                                int every) {
  if (surface.perSide() != perSide_ || cull.blocks() != perSide_)
    throw Error("CarveSchedule::plan: the surface blocks or the cull do not cover the record's volume");
  const uint8_t due = static_cast<uint8_t>(std::clamp(every, 1, kMaxEvery));
  list_.clear();
  carvedOnly_ = 0;
  const int n = perSide_;
  int32_t index = 0;
  for (int bz = 0; bz < n; ++bz)
    for (int by = 0; by < n; ++by) {
      const uint8_t* live = cull.viewRow(by, bz);  // the same block order: bx fastest
      const uint8_t* inside = cull.insideRow(by, bz);
      const bool anyLive = cull.anyLive(by, bz);
      uint8_t* age = &age_[static_cast<size_t>(index)];
      for (int bx = 0; bx < n; ++bx, ++index) {
        uint8_t a = age[bx];
        if (a < kNever - 1)
          ++a;  // this integration counts; kNever (never visited) stays, an old age saturates
        const bool carve = anyLive && live[bx] && a >= due;
        const bool band = surface.contains(bx, by, bz);
        if (carve || band) {
          list_.push_back(index);
          carvedOnly_ += carve && !band;
          // Seen in part, a block never carved whole stays due: its other part is carved when it comes into
          // view.
          if (inside[bx] || a != kNever) a = 0;
        }
        age[bx] = a;
      }
    }
  return list_;
}

}  // namespace sb
