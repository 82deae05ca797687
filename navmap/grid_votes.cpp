#include "navmap/grid_votes.h"

#include <algorithm>

namespace sb::navmap {

namespace {
int64_t floorDiv(int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }
}  // namespace

CellVotes& GridVotes::cell(int64_t ix, int64_t iy) {
  const int64_t cx = floorDiv(ix, kChunk), cy = floorDiv(iy, kChunk);
  Chunk& chunk = chunks_[key(cx, cy)];
  return chunk[size_t((iy - cy * kChunk) * kChunk + (ix - cx * kChunk))];
}

CellVotes GridVotes::get(int64_t ix, int64_t iy) const {
  const int64_t cx = floorDiv(ix, kChunk), cy = floorDiv(iy, kChunk);
  const auto it = chunks_.find(key(cx, cy));
  if (it == chunks_.end()) return {};
  return it->second[size_t((iy - cy * kChunk) * kChunk + (ix - cx * kChunk))];
}

void GridVotes::merge(const GridVotes& other) {
  for (const auto& [k, chunk] : other.chunks_) {
    Chunk& mine = chunks_[k];
    for (size_t i = 0; i < mine.size(); ++i) mine[i].add(chunk[i].surface, chunk[i].free);
  }
}

bool GridVotes::bounds(int64_t& minX, int64_t& minY, int64_t& maxX, int64_t& maxY) const {
  bool any = false;
  for (const auto& [k, chunk] : chunks_) {
    const int64_t cx = int32_t(uint32_t(k >> 32)), cy = int32_t(uint32_t(k & 0xffffffffu));
    for (int y = 0; y < kChunk; ++y)
      for (int x = 0; x < kChunk; ++x) {
        const CellVotes& v = chunk[size_t(y * kChunk + x)];
        if (v.surface == 0 && v.free == 0) continue;
        const int64_t ix = cx * kChunk + x, iy = cy * kChunk + y;
        if (!any) minX = maxX = ix, minY = maxY = iy, any = true;
        minX = std::min(minX, ix), maxX = std::max(maxX, ix), minY = std::min(minY, iy), maxY = std::max(maxY, iy);
      }
  }
  return any;
}

void VolumeVotes::merge(const VolumeVotes& other) {
  for (const auto& [k, v] : other.cells_) cells_[k].add(v.surface, v.free);
}

}  // namespace sb::navmap
