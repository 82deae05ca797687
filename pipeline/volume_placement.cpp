#include "pipeline/volume_placement.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <string>

#include "core/error.h"

namespace sb {

namespace {

int positiveModulo(int v, int n) {
  const int m = v % n;
  return m < 0 ? m + n : m;
}

}  // namespace

SbVoxelOffset VolumePlacement::offset() const {
  SbVoxelOffset o;
  o.x = positiveModulo(corner_.x(), resolution_);
  o.y = positiveModulo(corner_.y(), resolution_);
  o.z = positiveModulo(corner_.z(), resolution_);
  return o;
}

Eigen::Isometry3f VolumePlacement::toVolumeFrame(const Eigen::Isometry3f& T_camera_to_world) const {
  if (!moved()) return T_camera_to_world;
  Eigen::Isometry3f pose = T_camera_to_world;
  pose.translation() -= cornerMetres();
  return pose;
}

std::vector<VolumePlacement::Clear> VolumePlacement::moveTo(const Eigen::Vector3i& to) {
  std::vector<Clear> clears;
  for (int axis = 0; axis < 3; ++axis) {
    const int delta = to[axis] - corner_[axis];
    if (delta % kBlockVoxels != 0)
      throw Error("moving volume: a move of " + std::to_string(delta) + " voxels along axis " + std::to_string(axis) +
                  " is not a whole number of " + std::to_string(kBlockVoxels) + "-voxel blocks");
    if (delta == 0) continue;
    const int count = std::min(std::abs(delta), resolution_);
    const int offset = positiveModulo(corner_[axis], resolution_);
    // Leaving: logical planes [0, count) for a move up, [R - count, R) for a move down.
    const int firstLogical = delta > 0 ? 0 : resolution_ - count;
    Clear c;
    c.axis = axis;
    c.first = count == resolution_ ? 0 : positiveModulo(firstLogical + offset, resolution_);
    c.count = count;
    clears.push_back(c);
    corner_[axis] = to[axis];
  }
  return clears;
}

std::vector<BoxPiece> boxPieces(const std::array<int, 3>& first, const std::array<int, 3>& extent,
                                const SbVoxelOffset& offset, int resolution) {
  // Per axis: one or two runs (physical start, start in the box, length).
  std::array<std::vector<std::array<int, 3>>, 3> runs;
  const int o[3] = {offset.x, offset.y, offset.z};
  for (int a = 0; a < 3; ++a) {
    const int f = first[size_t(a)], n = extent[size_t(a)];
    if (f < 0 || n < 1 || f + n > resolution)
      throw Error("volume box of " + std::to_string(n) + " voxels from " + std::to_string(f) +
                  " along axis " + std::to_string(a) + " is not inside the cube of " +
                  std::to_string(resolution));
    const int start = positiveModulo(f + o[a], resolution);
    const int beforeWrap = std::min(n, resolution - start);
    runs[size_t(a)].push_back({start, 0, beforeWrap});
    if (beforeWrap < n) runs[size_t(a)].push_back({0, beforeWrap, n - beforeWrap});
  }
  std::vector<BoxPiece> pieces;
  for (const auto& z : runs[2])
    for (const auto& y : runs[1])
      for (const auto& x : runs[0])
        pieces.push_back(BoxPiece{{x[0], y[0], z[0]}, {x[1], y[1], z[1]}, {x[2], y[2], z[2]}});
  return pieces;
}

void shiftGrid(uint8_t* grid, int n, int axis, int cells, uint8_t empty, ThreadPool& pool) {
  if (axis < 0 || axis > 2) throw Error("shiftGrid: axis " + std::to_string(axis) + " is not 0 (x), 1 (y) or 2 (z)");
  if (cells == 0 || n <= 0) return;
  const size_t row = size_t(n), plane = size_t(n) * row;
  // Within one run of n elements of `stride` bytes, element i + cells moves to i; the ones that came in are
  // filled.
  const auto shiftRun = [&](uint8_t* run, size_t stride) {
    const int kept = n - std::abs(cells);
    if (kept <= 0) {
      std::memset(run, empty, size_t(n) * stride);
    } else if (cells > 0) {
      std::memmove(run, run + size_t(cells) * stride, size_t(kept) * stride);
      std::memset(run + size_t(kept) * stride, empty, size_t(cells) * stride);
    } else {
      std::memmove(run + size_t(-cells) * stride, run, size_t(kept) * stride);
      std::memset(run, empty, size_t(-cells) * stride);
    }
  };
  if (axis == 2) {
    shiftRun(grid, plane);
    return;
  }
  pool.parallelFor(0, n, 1, [&](int, int z0, int z1) {
    for (int z = z0; z < z1; ++z) {
      uint8_t* p = grid + size_t(z) * plane;
      if (axis == 1) {
        shiftRun(p, row);
      } else {
        for (int y = 0; y < n; ++y) shiftRun(p + size_t(y) * row, 1);
      }
    }
  });
}

}  // namespace sb
