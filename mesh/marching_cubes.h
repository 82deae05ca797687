#pragma once
// Surface extraction from the KinectFusion TSDF volume: the zero level set of the truncated signed distance
// becomes a welded triangle mesh.
//
// The algorithm is marching tetrahedra, a marching-cubes variant: every cell (the cube between 8 neighbouring
// voxel centres) is split into 6 tetrahedra that share the cell's main diagonal (the Kuhn / Freudenthal
// split). The split is the same translated pattern in every cell, so neighbouring cells cut their shared
// faces along the same diagonal and the surface has no cracks. The per-tetrahedron case table (16 sign
// cases) is derived programmatically at first use (see tetra_cases.h); no lookup tables are copied.
//
// Volume contract (the same layout the pipeline integrates into):
//   - a cube of resolution^3 voxels and side `size` metres;
//   - voxel (x, y, z) at index i = x + y*R + z*R*R holds two int16: data[2*i] = tsdf scaled so that 32767
//     means +1.0 (tsdf in [-1, 1] is the truncated SDF divided by mu, positive in front of the surface,
//     i.e. in free space), data[2*i+1] = weight (0 = never observed);
//   - voxel centre at ((x+0.5)*size/R, (y+0.5)*size/R, (z+0.5)*size/R) in the volume frame (metres).
// Cells with any corner below the minimum weight (and always those with a weight-0 corner) produce no
// triangles.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <vector>

namespace sb {

class ThreadPool;

// A borrowed view of a TSDF volume (does not own the data; see the contract above).
struct VolumeView {
  const int16_t* data = nullptr;  // 2 * resolution^3 int16 values, interleaved (tsdf, weight)
  int resolution = 0;             // voxels per side
  float size = 0.0f;              // side length of the cube, metres
  // A moving volume's cyclic buffer (kernels/volume.h): logical voxel v is stored at (v + offset) mod
  // resolution on each axis. All zero: a fixed volume.
  std::array<int, 3> offset{0, 0, 0};
  // A box of the cube instead of all of it (a slab that leaves a moving volume, pipeline/volume_window.h):
  // logical voxels first .. first + extent - 1 on each axis. The mesh is then in the box's frame (voxel
  // `first`'s centre at (0.5, 0.5, 0.5) voxels). All extents zero: the whole cube.
  std::array<int, 3> first{0, 0, 0};
  std::array<int, 3> extent{0, 0, 0};
  // `data` holds the box alone (a copy of a slab, BackendVolume::readVolumeBox): 2 * extent[0] * extent[1] *
  // extent[2] int16, x fastest, box voxel (x, y, z) at x + extent[0] * (y + extent[1] * z); `offset` and
  // `first` must then be 0. The mesh is the one of the same box read in place from the cube, bit for bit.
  bool boxOnly = false;
};

// tsdf value that means +1.0 in VolumeView::data.
constexpr float kTsdfScale = 32767.0f;

struct MeshOptions {
  // A voxel takes part only when its weight is >= minWeight. Values below 1 are treated as 1: a never
  // observed voxel (weight 0) never produces surface.
  int minWeight = 1;
};

// Triangle mesh in the volume frame (metres).
struct Mesh {
  std::vector<Eigen::Vector3f> vertices;                // metres, volume frame
  std::vector<Eigen::Vector3f> normals;                 // unit, one per vertex, from the TSDF gradient
  std::vector<std::array<uint32_t, 3>> triangles;       // counter-clockwise seen from outside (free space)
};

// Extracts the zero-level surface. Vertices on the same voxel-to-voxel edge are shared between all
// triangles that use it (no triangle soup), so a closed observed surface gives a closed mesh whose
// triangle normals point into free space (towards positive tsdf). Work is split into z-slabs run on
// `pool`; the output is identical for any thread count. Throws sb::Error on an invalid view.
Mesh extractMesh(const VolumeView& volume, const MeshOptions& options, ThreadPool& pool);
// Same, on ThreadPool::global().
Mesh extractMesh(const VolumeView& volume, const MeshOptions& options = {});

// Moves the mesh from the volume frame to another frame (e.g. world): rotates and translates vertices,
// rotates normals. Triangles are unchanged.
void transformMesh(Mesh& mesh, const Eigen::Isometry3f& T_volume_to_target);

}  // namespace sb
