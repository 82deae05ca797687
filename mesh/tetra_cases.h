#pragma once
// The case table of marching tetrahedra, derived programmatically (nothing copied).
//
// Cell corners are numbered c = bx | by << 1 | bz << 2 with offset (bx, by, bz) in voxels. The cell is split
// into 6 tetrahedra, one per permutation (a, b, c) of the axes: corners 0, e_a, e_a + e_b, 7 (a monotone
// path along the main diagonal). Every tetrahedron edge joins a lower corner `low` to low + d with d a
// non-zero 0/1 vector; the same edge seen from a neighbouring cell has the same global lower voxel and d,
// which is what welds vertices across cells.

#include <array>
#include <cstdint>

namespace sb::mesh_detail {

constexpr int kCellCorners = 8;
constexpr int kTetrahedraPerCell = 6;
constexpr int kTetraCorners = 4;
constexpr int kTetraCases = 1 << kTetraCorners;
constexpr int kEdgeDirections = 7;  // non-zero 0/1 offsets (1,0,0) ... (1,1,1)
constexpr int kMaxTrianglesPerCase = 2;

// An edge of the cell: from corner `low` to corner low | dir (dir = bitmask of the axes it steps along).
struct CellEdge {
  uint8_t low = 0;
  uint8_t dir = 0;  // 1..7
};

struct TetraCase {
  int triangleCount = 0;
  std::array<std::array<CellEdge, 3>, kMaxTrianglesPerCase> triangles{};
};

struct TetraTable {
  // The 4 cell corners of each tetrahedron, in chain order (each corner's bits contain the previous one's).
  std::array<std::array<uint8_t, kTetraCorners>, kTetrahedraPerCell> corners{};
  // cases[t][m]: triangles of tetrahedron t when bit k of m says corner k is inside (tsdf < 0). Triangles
  // are wound counter-clockwise seen from outside (normal towards positive tsdf).
  std::array<std::array<TetraCase, kTetraCases>, kTetrahedraPerCell> cases{};
};

// Built once, on first use (thread-safe static initialisation).
const TetraTable& tetraTable();

}  // namespace sb::mesh_detail
