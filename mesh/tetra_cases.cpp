#include "mesh/tetra_cases.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <stdexcept>

namespace sb::mesh_detail {

namespace {

// Corner offset in voxels.
Eigen::Vector3i cornerOffset(int corner) { return {corner & 1, (corner >> 1) & 1, (corner >> 2) & 1}; }

// Edge between two tetrahedron corners; in a chain the smaller corner (as a bit set) is the lower one.
CellEdge makeEdge(uint8_t u, uint8_t v) {
  const uint8_t low = std::min(u, v);
  const uint8_t high = std::max(u, v);
  return CellEdge{low, static_cast<uint8_t>(high ^ low)};
}

Eigen::Vector3i doubledMidpoint(const CellEdge& e) { return cornerOffset(e.low) + cornerOffset(e.low | e.dir); }

// Orders the triangle so that its normal points along `outward` (from the inside corners to the outside
// ones). With the cut points at edge midpoints the triangle is never degenerate, and moving the cut points
// along their edges (as the real tsdf values do) cannot flip it, so the winding holds for every input.
std::array<CellEdge, 3> orient(std::array<CellEdge, 3> tri, const Eigen::Vector3i& outward) {
  const Eigen::Vector3i p = doubledMidpoint(tri[0]);
  const Eigen::Vector3i n = (doubledMidpoint(tri[1]) - p).cross(doubledMidpoint(tri[2]) - p);
  const int side = n.dot(outward);
  if (side == 0) throw std::logic_error("marching tetrahedra: degenerate case triangle");
  if (side < 0) std::swap(tri[1], tri[2]);
  return tri;
}

TetraCase buildCase(const std::array<uint8_t, kTetraCorners>& corners, int mask) {
  std::array<int, kTetraCorners> in{}, out{};
  int nIn = 0, nOut = 0;
  Eigen::Vector3i sumIn = Eigen::Vector3i::Zero(), sumOut = Eigen::Vector3i::Zero();
  for (int k = 0; k < kTetraCorners; ++k) {
    if (mask & (1 << k)) {
      in[nIn++] = corners[k];
      sumIn += cornerOffset(corners[k]);
    } else {
      out[nOut++] = corners[k];
      sumOut += cornerOffset(corners[k]);
    }
  }
  TetraCase result;
  if (nIn == 0 || nOut == 0) return result;
  // Centroid(outside) - centroid(inside), scaled by nIn * nOut to stay integral.
  const Eigen::Vector3i outward = sumOut * nIn - sumIn * nOut;
  auto e = [](int u, int v) { return makeEdge(static_cast<uint8_t>(u), static_cast<uint8_t>(v)); };
  if (nIn == 1 || nOut == 1) {
    // One corner on its own side: one triangle cutting the three edges at that corner.
    const int lone = nIn == 1 ? in[0] : out[0];
    const std::array<int, 3> others = nIn == 1 ? std::array<int, 3>{out[0], out[1], out[2]}
                                               : std::array<int, 3>{in[0], in[1], in[2]};
    result.triangles[0] = orient({e(lone, others[0]), e(lone, others[1]), e(lone, others[2])}, outward);
    result.triangleCount = 1;
  } else {
    // Two inside (a, b), two outside (c, d): the cut is the quad ac, ad, bd, bc (consecutive points share
    // a face of the tetrahedron), split into two triangles along ac-bd.
    const int a = in[0], b = in[1], c = out[0], d = out[1];
    result.triangles[0] = orient({e(a, c), e(a, d), e(b, d)}, outward);
    result.triangles[1] = orient({e(a, c), e(b, d), e(b, c)}, outward);
    result.triangleCount = 2;
  }
  return result;
}

TetraTable buildTable() {
  TetraTable table;
  const int axisPermutations[kTetrahedraPerCell][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2},
                                                       {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int t = 0; t < kTetrahedraPerCell; ++t) {
    const int a = axisPermutations[t][0], b = axisPermutations[t][1];
    table.corners[t] = {0, static_cast<uint8_t>(1 << a), static_cast<uint8_t>((1 << a) | (1 << b)),
                        kCellCorners - 1};
    for (int m = 0; m < kTetraCases; ++m) table.cases[t][m] = buildCase(table.corners[t], m);
  }
  return table;
}

}  // namespace

const TetraTable& tetraTable() {
  static const TetraTable table = buildTable();
  return table;
}

}  // namespace sb::mesh_detail
