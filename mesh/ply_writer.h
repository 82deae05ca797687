#pragma once
// Writes a sb::Mesh as a PLY file (Stanford polygon format), readable by MeshLab, CloudCompare, Open3D.
//
// Layout: `vertex` elements with float x y z (metres) and, when the mesh has normals, float nx ny nz;
// `face` elements with `property list uchar uint vertex_indices` (always 3 indices). Binary bodies are
// little-endian on every host (bytes are written explicitly, not by memory dump).

#include "mesh/marching_cubes.h"

#include <string>

namespace sb {

enum class PlyFormat { BinaryLittleEndian, Ascii };

// Throws sb::Error naming `path` when the file cannot be created or written (sb::DiskFullError when the disk
// is full: core/disk_full.h), and when the mesh is inconsistent (normals count differs from vertices, a
// triangle index out of range).
void writePly(const std::string& path, const Mesh& mesh, PlyFormat format = PlyFormat::BinaryLittleEndian);

}  // namespace sb
