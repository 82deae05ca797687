#include "navmap/octomap_file.h"

#include <cstdio>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "navmap/voxel_votes.h"

#ifdef SB_HAVE_OCTOMAP
#include <octomap/OcTree.h>
#endif

namespace sb::navmap {

#ifdef SB_HAVE_OCTOMAP

bool octomapAvailable() { return true; }

bool writeOctomap(const std::string& path, const VolumeVotes& votes, const NavMapConfig& config, double voxelSizeM,
                  OctomapStats* stats) {
  const double res = config.octomapResolutionM;
  octomap::OcTree tree(res);
  const double expected = voxelsPerVolumeCell(config, voxelSizeM);
  OctomapStats s;
  votes.forEach([&](int32_t x, int32_t y, int32_t z, const CellVotes& v) {
    const CellState state = classifyCell(v, config.minOccupiedVoxels, config.freeShare, expected);
    if (state == CellState::unknown) return;
    const octomap::point3d centre(float((x + 0.5) * res), float((y + 0.5) * res), float((z + 0.5) * res));
    const bool occupied = state == CellState::occupied;
    tree.updateNode(centre, occupied ? tree.getClampingThresMaxLog() : tree.getClampingThresMinLog(), true);
    ++(occupied ? s.occupiedLeaves : s.freeLeaves);
  });
  tree.updateInnerOccupancy();
  tree.prune();
  s.treeBytes = tree.memoryUsage();
  // Into memory, then through the exclusive temporary (core/atomic_file.h): never a file opened by name.
  std::ostringstream bytes(std::ios::binary);
  if (!tree.writeBinary(bytes)) throw Error("cannot encode the OctoMap for '" + path + "'");
  const std::string data = bytes.str();
  writeFileAtomically(path, [&](std::FILE* file, const std::string& temporary) {
    if (std::fwrite(data.data(), 1, data.size(), file) != data.size())
      throw Error("cannot write the OctoMap '" + temporary + "' (check the disk and its permissions)");
  });
  if (stats) *stats = s;
  return true;
}

#else

bool octomapAvailable() { return false; }

bool writeOctomap(const std::string&, const VolumeVotes&, const NavMapConfig&, double, OctomapStats*) {
  return false;
}

#endif

}  // namespace sb::navmap
