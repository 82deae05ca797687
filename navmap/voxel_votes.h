#pragma once
// The voxels of a TSDF box cast their votes for the map's cells (issue 45): a voxel observed (weight > 0) at
// most surfaceDepthM behind the surface (tsdf in [-surfaceDepthM / mu, 0]) is surface; observed in front of
// any surface (tsdf > 0) it is free; unobserved it does not vote. voteGrid takes the voxels whose centre lies
// in the robot's band (map z in [bandMinM, bandMaxM]) and votes for the 2D cell below them; voteVolume takes
// every voxel and votes for its 3D cell of the OctoMap's resolution. Both read only the box they are given:
// a slab that leaves the moving volume, or the volume at the grid's update period (never per frame).

#include <Eigen/Geometry>
#include <array>
#include <cstdint>

#include "navmap/grid_votes.h"
#include "navmap/navmap_config.h"

namespace sb::navmap {

// A box of TSDF voxels: logical voxels first .. first + extent - 1 of a storage of dims voxels per axis, the
// logical voxel v stored at (v + offset) mod dims (kernels/volume.h's cyclic buffer; 0 for a copy), x fastest,
// 2 int16 per voxel (tsdf scaled by 32767, weight).
struct VoxelBox {
  const int16_t* data = nullptr;
  std::array<int, 3> dims{};
  std::array<int, 3> offset{};
  std::array<int, 3> first{};
  std::array<int, 3> extent{};
  Eigen::Vector3d corner = Eigen::Vector3d::Zero();  // world, metres: the lower corner of logical voxel (0,0,0)
  double voxelSizeM = 0.0;
  double muM = 0.1;  // the TSDF's truncation distance
};

void voteGrid(const VoxelBox& box, const Eigen::Isometry3d& T_world_to_map, const NavMapConfig& config,
              GridVotes& out);
void voteVolume(const VoxelBox& box, const Eigen::Isometry3d& T_world_to_map, const NavMapConfig& config,
                VolumeVotes& out);

// The voxels a 2D cell's band holds (the free share's denominator), and a 3D cell's.
double bandVoxelsPerCell(const NavMapConfig& config, double voxelSizeM);
double voxelsPerVolumeCell(const NavMapConfig& config, double voxelSizeM);

}  // namespace sb::navmap
