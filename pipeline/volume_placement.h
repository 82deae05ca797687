#pragma once
// Where a moving volume lies (docs/moving-volume.md), the host side of kernels/volume.h's cyclic buffer, shared
// by both backends: the volume's corner in the world (whole voxels), the cyclic offset (the corner modulo the
// side), the pose in the volume's frame, and what a move clears. A volume that never moved has its corner at 0:
// the volume frame is the world frame and every pose passes through unchanged, bit for bit.

#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <vector>

#include "core/thread_pool.h"
#include "kernels/volume.h"

namespace sb {

class VolumePlacement {
 public:
  // Moves are whole multiples of this many voxels (the CPU backend's culling blocks; the skipping grid's
  // blocks of 4 voxels divide it).
  static constexpr int kBlockVoxels = 8;

  VolumePlacement(int resolution, float voxelSize) : resolution_(resolution), voxelSize_(voxelSize) {}

  // The corner of the volume in the world, voxels (the cube [0, R)^3 before any move).
  const Eigen::Vector3i& corner() const { return corner_; }
  bool moved() const { return !corner_.isZero(); }
  // The same in metres.
  Eigen::Vector3f cornerMetres() const { return corner_.cast<float>() * voxelSize_; }
  // The cyclic offset: the corner modulo R on each axis, in [0, R).
  SbVoxelOffset offset() const;
  // A world pose in the volume frame (the translation less the corner); unchanged when the volume never moved.
  Eigen::Isometry3f toVolumeFrame(const Eigen::Isometry3f& T_camera_to_world) const;

  // The physical planes a move clears on one axis: `count` planes from `first`, wrapping at R.
  struct Clear {
    int axis = 0;
    int first = 0;
    int count = 0;
  };
  // Moves the corner to `to` (each axis a multiple of kBlockVoxels; throws sb::Error otherwise) and returns, per
  // axis that moved, the planes that left (all R when it moved by R or more): the caller clears them. Logical
  // voxel v then holds what logical voxel v + (to - corner) held.
  std::vector<Clear> moveTo(const Eigen::Vector3i& to);

 private:
  int resolution_;
  float voxelSize_;  // metres
  Eigen::Vector3i corner_ = Eigen::Vector3i::Zero();
};

// A logical box of the cyclic buffer (logical voxels first .. first + extent - 1 per axis, inside [0, R)) as
// the physical boxes that store it: per axis the range starts at physical (first + offset) mod R and splits
// in two where it wraps, so a box is 1 to 8 pieces. Each piece: where it is stored, where it lies in the box,
// its size (voxels). For reading a slab alone (BackendVolume::readVolumeBox). Throws sb::Error on a box
// outside the cube.
struct BoxPiece {
  std::array<int, 3> physical{};  // the piece's first voxel in the buffer
  std::array<int, 3> inBox{};     // ... in the box
  std::array<int, 3> extent{};    // voxels per axis
};
std::vector<BoxPiece> boxPieces(const std::array<int, 3>& first, const std::array<int, 3>& extent,
                                const SbVoxelOffset& offset, int resolution);

// Moves the content of an n^3 grid of one-byte cells (x fastest) by `cells` along `axis` (0 x, 1 y, 2 z): cell v
// then holds what cell v + cells held; the cells that came in get `empty`. |cells| >= n fills the whole grid.
// For the empty-space skipping grid, which is kept in logical blocks and follows the volume (its 1/64 of the
// voxel count is copied; the voxels are not).
void shiftGrid(uint8_t* grid, int n, int axis, int cells, uint8_t empty, ThreadPool& pool);

}  // namespace sb
