#pragma once
// The votes the TSDF's voxels cast for the cells of the map (issue 45): per 2D cell (its band) or 3D cell, the
// surface voxels and the voxels observed in front of any surface. Sparse, in chunks of 64 x 64 cells (2D) or a
// hash of cells (3D), so memory follows the area explored: 4 bytes per 2D cell of an explored chunk (64 x 64
// cells of 5 cm: 16 KiB per 3.2 m x 3.2 m), about 40 bytes per observed 3D cell.

#include <array>
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <unordered_map>

namespace sb::navmap {

struct CellVotes {
  uint16_t surface = 0;  // saturating
  uint16_t free = 0;
  void add(uint32_t s, uint32_t f) {
    surface = uint16_t(std::min<uint32_t>(uint32_t(surface) + s, 65535u));
    free = uint16_t(std::min<uint32_t>(uint32_t(free) + f, 65535u));
  }
};

enum class CellState : int8_t { unknown = -1, free = 0, occupied = 100 };  // nav_msgs/OccupancyGrid values

// A cell's state from its votes: occupied with at least `minSurface` surface voxels, else free when at least
// `freeShare` of the `expectedVoxels` voxels it holds were observed free, else unknown.
inline CellState classifyCell(const CellVotes& v, int minSurface, double freeShare, double expectedVoxels) {
  if (v.surface >= minSurface) return CellState::occupied;
  if (v.free > 0 && double(v.free) >= freeShare * expectedVoxels) return CellState::free;
  return CellState::unknown;
}

class GridVotes {
 public:
  static constexpr int kChunk = 64;  // cells per chunk side
  using Chunk = std::array<CellVotes, kChunk * kChunk>;

  void add(int64_t ix, int64_t iy, uint32_t surface, uint32_t free) { cell(ix, iy).add(surface, free); }
  CellVotes get(int64_t ix, int64_t iy) const;
  void clear() { chunks_.clear(); }
  void merge(const GridVotes& other);
  // The cells' bounds (inclusive), false when empty.
  bool bounds(int64_t& minX, int64_t& minY, int64_t& maxX, int64_t& maxY) const;
  size_t bytes() const { return chunks_.size() * sizeof(Chunk); }
  // The chunks, f(cx, cy, chunk) with chunk (cx, cy) holding cells cx * kChunk .. cx * kChunk + kChunk - 1 (x)
  // and likewise y, cell (x, y) at chunk[y * kChunk + x]; in no particular order (a map store, kept_votes.h).
  template <typename F>
  void forEachChunk(F&& f) const {
    for (const auto& [k, c] : chunks_) f(int32_t(uint32_t(k >> 32)), int32_t(uint32_t(k & 0xffffffffu)), c);
  }
  Chunk& chunk(int32_t cx, int32_t cy) { return chunks_[key(cx, cy)]; }

 private:
  static uint64_t key(int64_t cx, int64_t cy) { return (uint64_t(uint32_t(cx)) << 32) | uint32_t(cy); }
  CellVotes& cell(int64_t ix, int64_t iy);
  std::unordered_map<uint64_t, Chunk> chunks_;
};

// 3D cells of the OctoMap's resolution, keyed by their integer coordinates in the map frame.
class VolumeVotes {
 public:
  void add(int32_t x, int32_t y, int32_t z, uint32_t surface, uint32_t free) { cells_[key(x, y, z)].add(surface, free); }
  void merge(const VolumeVotes& other);
  void clear() { cells_.clear(); }
  size_t size() const { return cells_.size(); }
  template <typename F>
  void forEach(F&& f) const {
    for (const auto& [k, v] : cells_) f(int32_t(int64_t(k >> 42) - kBias), int32_t(int64_t((k >> 21) & kMask) - kBias),
                                         int32_t(int64_t(k & kMask) - kBias), v);
  }

 private:
  static constexpr uint64_t kMask = (uint64_t(1) << 21) - 1;
  static constexpr int64_t kBias = int64_t(1) << 20;
  static uint64_t key(int32_t x, int32_t y, int32_t z) {
    return (uint64_t(int64_t(x) + kBias) << 42) | ((uint64_t(int64_t(y) + kBias) & kMask) << 21) |
           (uint64_t(int64_t(z) + kBias) & kMask);
  }
  std::unordered_map<uint64_t, CellVotes> cells_;
};

}  // namespace sb::navmap
