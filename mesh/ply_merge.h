#pragma once
// One PLY from many (the moving volume's map, issue 30): the parts that writePly wrote (binary little-endian,
// with normals) and a last mesh, concatenated into one file without holding the parts in memory.

#include <string>
#include <vector>

#include "mesh/marching_cubes.h"

namespace sb {

// Writes `path` (aside first, then renamed: a killed process never leaves half a file) with the vertices and
// triangles of every part, in order, then `last`'s. Returns the number of triangles. Throws sb::Error naming
// the part that cannot be read or is not a binary PLY with normals as writePly writes it, or `path`.
size_t writeMergedPly(const std::string& path, const std::vector<std::string>& parts, const Mesh& last);

}  // namespace sb
