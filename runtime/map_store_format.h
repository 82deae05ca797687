#pragma once
// The files of a map store (runtime/map_store.h; issue 55), encoded and checked. Every file is little-endian
// with fixed-size fields (the same bytes on x86-64 and armhf), starts with a magic and the format version and
// ends its header with the FNV-1a 64 checksum of its payload, so a truncated or altered file is refused with
// its name, never read as a map.
//
// A slab file (slabs/slab-NNNNNN.tsdf) holds a box of TSDF voxels in the world's voxel grid, run-length coded:
//   "SBTSDF\n\0", u32 version, i32 first[3] (world voxels), i32 extent[3], u64 payload bytes, u64 checksum,
//   payload: runs of (u32 unobserved voxels skipped, u32 observed voxels n, n x (i16 tsdf, i16 weight)), x
//   fastest, covering the box. Unobserved voxels (weight 0) cost nothing: a corridor's slab of 81 x 256 x 256
//   voxels (20 MiB raw) is mostly air and holds a tenth of that or less.
// The keyframe file (keyframes.bin): "SBKEYF\n\0", u32 version, u32 keyframes, u32 fern codes per keyframe,
// u64 payload bytes, u64 checksum, payload: per keyframe u64 frame, f64 pose[12] (T_camera_to_world, the
// store's frame, rows of the 3x4 matrix), u8 codes[ferns].
// A state file (runtime/map_store_bytes.h): magic, u32 version, u64 payload bytes, u64 checksum, payload (its
// version says its layout: StateFile::version the newest):
//   navmap.bin    "SBNAVV\n\0": the navigation map's frame and votes (navmap/kept_votes.h)
//   odometry.bin  "SBODOM\n\0": the wheels' learnt calibration (runtime/kept_odometry.h)

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "pipeline/volume_window.h"
#include "reloc/keyframe_database.h"

namespace sb::mapstore {

constexpr uint32_t kFormatVersion = 1;

// The store's state files: their names, magics and the newest version of their payload this build writes (it
// reads every version from kFormatVersion on: an older file is read as what it holds).
struct StateFile {
  const char* name;
  char magic[8];
  const char* what;  // for a message
  uint32_t version;
};
inline constexpr StateFile kNavmapFile{"navmap.bin", {'S', 'B', 'N', 'A', 'V', 'V', '\n', '\0'}, "map store navigation map",
                                       kFormatVersion};
// Version 2 adds the odometry's clock offset and the mount its correction was learnt against
// (runtime/kept_odometry.h).
inline constexpr StateFile kOdometryFile{"odometry.bin", {'S', 'B', 'O', 'D', 'O', 'M', '\n', '\0'},
                                         "map store odometry calibration", 2};

uint64_t fnv1a64(const uint8_t* data, size_t bytes);

// A box of TSDF in the world's voxel grid (voxel i covers [i, i + 1) * voxel size, metres).
struct SlabBox {
  std::array<int, 3> first{};   // world voxels
  std::array<int, 3> extent{};  // voxels per axis
  uint64_t voxels() const { return uint64_t(extent[0]) * uint64_t(extent[1]) * uint64_t(extent[2]); }
  bool intersects(const SlabBox& other) const;
  SlabBox intersection(const SlabBox& other) const;  // empty extent when they do not meet
};

// The bytes of a slab file for `voxels` (2 int16 per voxel, VolumeSlab's layout) over `box`; empty when no
// voxel of it is observed (nothing worth keeping).
std::vector<uint8_t> encodeSlab(const SlabBox& box, const int16_t* voxels);

// The header of the slab file `path` (its payload checked against the checksum); throws sb::Error naming the
// file when it is truncated, altered, not a slab file, or of another format version.
SlabBox readSlabHeader(const std::string& path);

// Copies the observed voxels of slab file `path` that lie in `target` into `out` (target's layout, 2 int16 per
// voxel, x fastest), leaving the others as they are. Throws as readSlabHeader.
void mergeSlab(const std::string& path, const SlabBox& target, int16_t* out);
// The same for a slab file's bytes kept in memory (an ordinary run's kept slabs, runtime/map_store.h); `name`
// says which slab in an error.
void mergeSlab(const std::vector<uint8_t>& bytes, const std::string& name, const SlabBox& target, int16_t* out);

std::vector<uint8_t> encodeKeyframes(const std::vector<const Keyframe*>& keyframes);
// Throws sb::Error naming `path` when it is truncated, altered, or of another format version.
std::vector<Keyframe> readKeyframes(const std::string& path);

}  // namespace sb::mapstore
