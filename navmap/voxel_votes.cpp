#include "navmap/voxel_votes.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace sb::navmap {

namespace {

constexpr float kTsdfScale = 32767.0f;

struct Classifier {
  int16_t surfaceLimit;  // tsdf at or above this (and <= 0): surface
  explicit Classifier(const NavMapConfig& c, double mu)
      : surfaceLimit(int16_t(-std::min(1.0, c.surfaceDepthM / mu) * kTsdfScale)) {}
  // 0 unobserved, 1 free, 2 surface, 3 deep behind a surface (no vote)
  int operator()(const int16_t* voxel) const {
    if (voxel[1] <= 0) return 0;
    if (voxel[0] > 0) return 1;
    return voxel[0] >= surfaceLimit ? 2 : 3;
  }
};

int wrap(int v, int o, int dims) {
  const int p = v + o;
  return p >= dims ? p - dims : p;
}

// Map-frame position of logical voxel v's centre: origin + axes * v.
struct VoxelToMap {
  Eigen::Vector3d origin;
  Eigen::Matrix3d axes;  // column k: the map-frame step of one voxel along storage axis k
  VoxelToMap(const VoxelBox& box, const Eigen::Isometry3d& T) {
    axes = T.linear() * box.voxelSizeM;
    origin = T * (box.corner + Eigen::Vector3d::Constant(0.5 * box.voxelSizeM));
  }
  Eigen::Vector3d at(double x, double y, double z) const { return origin + axes * Eigen::Vector3d(x, y, z); }
};

// The box's map-frame bounds (its eight corner voxels' centres).
void mapBounds(const VoxelBox& box, const VoxelToMap& m, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d p = m.at(box.first[0] + ((c & 1) ? box.extent[0] - 1 : 0),
                                   box.first[1] + ((c & 2) ? box.extent[1] - 1 : 0),
                                   box.first[2] + ((c & 4) ? box.extent[2] - 1 : 0));
    lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  }
}

}  // namespace

double bandVoxelsPerCell(const NavMapConfig& c, double voxel) {
  return (c.resolutionM / voxel) * (c.resolutionM / voxel) * ((c.bandMaxM - c.bandMinM) / voxel);
}

double voxelsPerVolumeCell(const NavMapConfig& c, double voxel) { return std::pow(c.octomapResolutionM / voxel, 3); }

void voteGrid(const VoxelBox& box, const Eigen::Isometry3d& T_world_to_map, const NavMapConfig& config,
              GridVotes& out) {
  if (box.extent[0] <= 0 || box.extent[1] <= 0 || box.extent[2] <= 0) return;
  const VoxelToMap m(box, T_world_to_map);
  const Classifier classify(config, box.muM);
  // The storage axis most nearly vertical in the map: each column along it crosses the band in one run.
  int u = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(m.axes(2, k)) > std::abs(m.axes(2, u))) u = k;
  const int a = (u + 1) % 3, b = (u + 2) % 3;
  Eigen::Vector3d lo, hi;
  mapBounds(box, m, lo, hi);
  const double res = config.resolutionM;
  const int64_t x0 = int64_t(std::floor(lo.x() / res)), y0 = int64_t(std::floor(lo.y() / res));
  const int64_t nx = int64_t(std::floor(hi.x() / res)) - x0 + 1, ny = int64_t(std::floor(hi.y() / res)) - y0 + 1;
  std::vector<uint32_t> surface(size_t(nx * ny), 0), free(size_t(nx * ny), 0);
  const double dz = m.axes(2, u);
  for (int j = box.first[b]; j < box.first[b] + box.extent[b]; ++j)
    for (int i = box.first[a]; i < box.first[a] + box.extent[a]; ++i) {
      Eigen::Vector3d v;
      v[a] = i, v[b] = j, v[u] = 0;
      const Eigen::Vector3d base = m.origin + m.axes * v;
      // The voxels along u whose centre is in the band: bandMin <= base.z + dz * k <= bandMax.
      double k0 = (config.bandMinM - base.z()) / dz, k1 = (config.bandMaxM - base.z()) / dz;
      if (k0 > k1) std::swap(k0, k1);
      const int kb = std::max(box.first[u], int(std::ceil(k0)));
      const int ke = std::min(box.first[u] + box.extent[u] - 1, int(std::floor(k1)));
      if (kb > ke) continue;
      int coords[3];
      coords[a] = wrap(i, box.offset[a], box.dims[a]);
      coords[b] = wrap(j, box.offset[b], box.dims[b]);
      for (int k = kb; k <= ke; ++k) {
        coords[u] = wrap(k, box.offset[u], box.dims[u]);
        const size_t index = size_t(coords[0]) + size_t(box.dims[0]) * (size_t(coords[1]) + size_t(box.dims[1]) * size_t(coords[2]));
        const int cls = classify(box.data + 2 * index);
        if (cls != 1 && cls != 2) continue;
        const double px = base.x() + m.axes(0, u) * k, py = base.y() + m.axes(1, u) * k;
        const int64_t cx = int64_t(std::floor(px / res)) - x0, cy = int64_t(std::floor(py / res)) - y0;
        const size_t cell = size_t(std::clamp<int64_t>(cy, 0, ny - 1) * nx + std::clamp<int64_t>(cx, 0, nx - 1));
        (cls == 2 ? surface : free)[cell] += 1;
      }
    }
  for (int64_t y = 0; y < ny; ++y)
    for (int64_t x = 0; x < nx; ++x) {
      const size_t cell = size_t(y * nx + x);
      if (surface[cell] || free[cell]) out.add(x0 + x, y0 + y, surface[cell], free[cell]);
    }
}

void voteVolume(const VoxelBox& box, const Eigen::Isometry3d& T_world_to_map, const NavMapConfig& config,
                VolumeVotes& out) {
  if (config.octomapResolutionM <= 0.0 || box.extent[0] <= 0 || box.extent[1] <= 0 || box.extent[2] <= 0) return;
  const VoxelToMap m(box, T_world_to_map);
  const Classifier classify(config, box.muM);
  Eigen::Vector3d lo, hi;
  mapBounds(box, m, lo, hi);
  const double inv = 1.0 / config.octomapResolutionM;
  const Eigen::Vector3i c0((lo * inv).array().floor().cast<int>());
  const Eigen::Vector3i n = (hi * inv).array().floor().cast<int>().matrix() - c0 + Eigen::Vector3i::Ones();
  std::vector<uint32_t> surface(size_t(n.prod()), 0), free(size_t(n.prod()), 0);
  // Blocks of k^3 voxels (k voxels: the OctoMap's leaf, rounded) vote for the leaf of their centre: one
  // transform per block, the voxels themselves only classified (a tilted map frame moves a block's voxels by
  // at most half a leaf).
  const int k = std::max(1, int(std::lround(config.octomapResolutionM / box.voxelSizeM)));
  for (int bz = box.first[2]; bz < box.first[2] + box.extent[2]; bz += k)
    for (int by = box.first[1]; by < box.first[1] + box.extent[1]; by += k)
      for (int bx = box.first[0]; bx < box.first[0] + box.extent[0]; bx += k) {
        const int ez = std::min(bz + k, box.first[2] + box.extent[2]), ey = std::min(by + k, box.first[1] + box.extent[1]),
                  ex = std::min(bx + k, box.first[0] + box.extent[0]);
        uint32_t s = 0, f = 0;
        for (int z = bz; z < ez; ++z)
          for (int y = by; y < ey; ++y) {
            const size_t row = size_t(box.dims[0]) * (size_t(wrap(y, box.offset[1], box.dims[1])) +
                                                      size_t(box.dims[1]) * size_t(wrap(z, box.offset[2], box.dims[2])));
            for (int x = bx; x < ex; ++x) {
              const int cls = classify(box.data + 2 * (row + size_t(wrap(x, box.offset[0], box.dims[0]))));
              s += cls == 2, f += cls == 1;
            }
          }
        if (s == 0 && f == 0) continue;
        const Eigen::Vector3d p = m.at(0.5 * (bx + ex - 1), 0.5 * (by + ey - 1), 0.5 * (bz + ez - 1)) * inv;
        const Eigen::Vector3i c = p.array().floor().cast<int>().matrix() - c0;
        const Eigen::Vector3i cc = c.cwiseMax(Eigen::Vector3i::Zero()).cwiseMin(n - Eigen::Vector3i::Ones());
        const size_t cell = size_t(cc.x()) + size_t(n.x()) * (size_t(cc.y()) + size_t(n.y()) * size_t(cc.z()));
        surface[cell] += s, free[cell] += f;
      }
  for (int z = 0; z < n.z(); ++z)
    for (int y = 0; y < n.y(); ++y)
      for (int x = 0; x < n.x(); ++x) {
        const size_t cell = size_t(x) + size_t(n.x()) * (size_t(y) + size_t(n.y()) * size_t(z));
        if (surface[cell] || free[cell]) out.add(c0.x() + x, c0.y() + y, c0.z() + z, surface[cell], free[cell]);
      }
}

}  // namespace sb::navmap
