#pragma once
// map.bt (issue 45): the 3D cells of the navigation map as an OctoMap (Hornung et al. 2013; liboctomap's
// binary tree: each leaf free or occupied), at NavMapConfig::octomapResolutionM. The liboctomap headers are
// included by octomap_file.cpp alone; a build without liboctomap-dev (SB_HAVE_OCTOMAP unset) writes no map.bt
// and says so.

#include <cstddef>
#include <string>

#include "navmap/grid_votes.h"
#include "navmap/navmap_config.h"

namespace sb::navmap {

struct OctomapStats {
  size_t occupiedLeaves = 0, freeLeaves = 0;  // cells given to the tree
  size_t treeBytes = 0;                       // OcTree::memoryUsage() after pruning
};

// True when this build has liboctomap.
bool octomapAvailable();

// Writes `path` atomically from the cells of `votes` (classifyCell over a 3D cell's voxels). Throws sb::Error
// naming the file; without liboctomap returns false and writes nothing.
bool writeOctomap(const std::string& path, const VolumeVotes& votes, const NavMapConfig& config, double voxelSizeM,
                  OctomapStats* stats = nullptr);

}  // namespace sb::navmap
