#pragma once
// The navigation map kept in a map store (issue 55; runtime/map_store.h, docs/map-store.md): the map frame and
// the votes of the grid and of map.bt's 3D cells, so that a run continued in the store writes map.pgm/yaml/bt
// covering every run in it, in one frame. navmap.bin is a state file of the store (runtime/map_store_format.h:
// magic, version, payload size and checksum); its payload, little-endian:
//   f64 T_world_to_map[12] (rows of the 3x4 matrix), u32 n, n bytes of the frame's source (at most 4096),
//   f64 resolution_m, band_min_m, band_max_m, surface_depth_m, octomap_resolution_m (the settings the votes were
//   cast with: a run with others is refused),
//   u32 chunks, per chunk (by cx, then cy) i32 cx, i32 cy and runs covering its 64 x 64 cells (y rows, x fastest):
//   (u16 cells without a vote skipped, u16 cells n, n x (u16 surface, u16 free)),
//   u32 runs of 3D cells neighbours along z (sorted by x, y, z), per run i32 x, y, z (the first), u16 cells n,
//   n x (u16 surface, u16 free).
// Its size follows the area explored, not the time: votes saturate at 65535 and a revisit adds none.

#include <cstdint>
#include <string>
#include <vector>

#include "navmap/grid_votes.h"
#include "navmap/map_frame.h"
#include "navmap/navmap_config.h"

namespace sb::navmap {

struct KeptVotes {
  MapFrame frame;
  GridVotes grid;
  VolumeVotes cells;
};

// navmap.bin's payload for `votes` cast with `config`.
std::vector<uint8_t> encodeKeptVotes(const KeptVotes& votes, const NavMapConfig& config);
// The votes of a navmap.bin payload read from `path`. Throws sb::Error naming `path` when the payload is
// malformed, or when its votes were cast with other settings than `config`'s (naming the setting).
KeptVotes decodeKeptVotes(const std::vector<uint8_t>& payload, const std::string& path, const NavMapConfig& config);

}  // namespace sb::navmap
