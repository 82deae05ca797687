#include "mesh/marching_cubes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>

#include "core/error.h"
#include "core/thread_pool.h"
#include "mesh/mesh_pieces.h"
#include "mesh/tetra_cases.h"

namespace sb {

namespace {

using namespace mesh_detail;

// Cells along z per parallel work item. Output does not depend on it (slabs are merged in order).
constexpr int kSlabCells = 4;
constexpr int kAxes = 3;
constexpr int kZAxisBit = 4;  // the z bit of a corner index / edge direction

// Read-only access to the interleaved (tsdf, weight) volume.
class VolumeSampler {
 public:
  VolumeSampler(const VolumeView& v, int minWeight) : data_(v.data), minWeight_(std::max(1, minWeight)) {
    const bool box = v.extent[0] > 0;
    for (int a = 0; a < kAxes; ++a) {
      n_[a] = box ? v.extent[size_t(a)] : v.resolution;
      // Box voxel i of this axis is logical voxel first + i, stored at physical (first + i + offset) mod R;
      // in a box stored alone, at i.
      physical_[a].resize(size_t(n_[a]));
      for (int i = 0; i < n_[a]; ++i)
        physical_[a][size_t(i)] =
            v.boxOnly ? i : ((box ? v.first[size_t(a)] : 0) + i + v.offset[size_t(a)]) % v.resolution;
    }
    rowVoxels_ = v.boxOnly ? n_[0] : v.resolution;
    planeVoxels_ = int64_t(rowVoxels_) * (v.boxOnly ? n_[1] : v.resolution);
  }

  int side(int axis) const { return n_[axis]; }  // voxels along the axis
  // The box's own numbering of voxel (x, y, z) (the edge keys).
  int64_t key(int x, int y, int z) const { return x + int64_t(n_[0]) * (y + int64_t(n_[1]) * z); }
  // Where voxel (x, y, z) of the box is stored.
  int64_t index(int x, int y, int z) const {
    return physical_[0][size_t(x)] + rowVoxels_ * physical_[1][size_t(y)] +
           planeVoxels_ * physical_[2][size_t(z)];
  }
  bool valid(int64_t i) const { return data_[2 * i + 1] >= minWeight_; }
  float tsdf(int64_t i) const { return data_[2 * i] / kTsdfScale; }

  // Gradient of the tsdf at a valid voxel (per voxel): central differences, one-sided where a neighbour
  // is outside the volume or not observed enough.
  Eigen::Vector3f gradient(const Eigen::Vector3i& p) const {
    Eigen::Vector3f g;
    const float centre = tsdf(index(p.x(), p.y(), p.z()));
    for (int a = 0; a < kAxes; ++a) {
      Eigen::Vector3i lo = p, hi = p;
      lo[a] -= 1;
      hi[a] += 1;
      const bool hasLo = lo[a] >= 0 && valid(index(lo.x(), lo.y(), lo.z()));
      const bool hasHi = hi[a] < n_[a] && valid(index(hi.x(), hi.y(), hi.z()));
      const float fLo = hasLo ? tsdf(index(lo.x(), lo.y(), lo.z())) : centre;
      const float fHi = hasHi ? tsdf(index(hi.x(), hi.y(), hi.z())) : centre;
      const int span = int(hasLo) + int(hasHi);
      g[a] = span == 0 ? 0.0f : (fHi - fLo) / static_cast<float>(span);
    }
    return g;
  }

 private:
  const int16_t* data_;
  int64_t rowVoxels_ = 0, planeVoxels_ = 0;  // strides of y and z in `data_`
  int n_[kAxes];
  std::vector<int> physical_[kAxes];
  int minWeight_;
};

Eigen::Vector3i cornerOffset(int corner) { return {corner & 1, (corner >> 1) & 1, (corner >> 2) & 1}; }

// A global edge: its lower voxel's index times kEdgeDirections plus (direction - 1).
uint64_t edgeKey(int64_t lowVoxel, int dir) { return uint64_t(lowVoxel) * kEdgeDirections + uint64_t(dir - 1); }

struct DecodedEdge {
  Eigen::Vector3i low;
  int dir;
};

DecodedEdge decodeEdge(uint64_t key, int nx, int ny) {
  const uint64_t voxel = key / kEdgeDirections;
  const int dir = int(key % kEdgeDirections) + 1;
  const uint64_t ux = uint64_t(nx), uy = uint64_t(ny);
  return {Eigen::Vector3i(int(voxel % ux), int((voxel / ux) % uy), int(voxel / (ux * uy))), dir};
}

// Triangles of cells z in [z0, z1), with vertices indexed locally in first-use order.
struct SlabMesh {
  std::vector<uint64_t> keys;
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Eigen::Vector3f> normals;
  std::vector<std::array<uint32_t, 3>> triangles;
};

class SlabExtractor {
 public:
  SlabExtractor(const VolumeSampler& volume, float voxelSize) : volume_(volume), voxelSize_(voxelSize) {}

  void run(int z0, int z1, SlabMesh& out) {
    out_ = &out;
    local_.clear();
    const int nx = volume_.side(0), ny = volume_.side(1);
    const TetraTable& table = tetraTable();
    std::vector<uint8_t> lower(size_t(nx) * size_t(ny)), upper(lower.size());
    classifyPlane(z0, upper);
    for (int z = z0; z < z1; ++z) {
      lower.swap(upper);
      classifyPlane(z + 1, upper);
      for (int y = 0; y + 1 < ny; ++y) {
        // Corner c of cell (x, y) is rows[c >> 1][x + (c & 1)]: rows ordered (y, z), (y+1, z), (y, z+1), (y+1, z+1).
        const size_t row = size_t(nx) * size_t(y);
        const std::array<const uint8_t*, 4> rows = {&lower[row], &lower[row + size_t(nx)], &upper[row],
                                                    &upper[row + size_t(nx)]};
        for (int x = 0; x + 1 < nx; ++x) {
          std::array<uint8_t, kCellCorners> f;
          for (int c = 0; c < kCellCorners; ++c) f[size_t(c)] = rows[size_t(c >> 1)][x + (c & 1)];
          uint8_t all = f[0], any = f[0];
          for (int c = 1; c < kCellCorners; ++c) {
            all &= f[size_t(c)];
            any |= f[size_t(c)];
          }
          // Skip cells not fully observed, and cells entirely inside or entirely outside.
          if (!(all & kObservedFlag) || (all & kInsideFlag) || !(any & kInsideFlag)) continue;
          int insideMask = 0;
          for (int c = 0; c < kCellCorners; ++c)
            if (f[size_t(c)] & kInsideFlag) insideMask |= 1 << c;
          const Eigen::Vector3i cell(x, y, z);
          for (int t = 0; t < kTetrahedraPerCell; ++t) {
            int m = 0;
            for (int k = 0; k < kTetraCorners; ++k)
              if (insideMask & (1 << table.corners[t][k])) m |= 1 << k;
            const TetraCase& tc = table.cases[t][m];
            for (int n = 0; n < tc.triangleCount; ++n) {
              std::array<uint32_t, 3> tri;
              for (int v = 0; v < 3; ++v) tri[v] = vertexOn(cell, tc.triangles[n][v]);
              out.triangles.push_back(tri);
            }
          }
        }
      }
    }
  }

 private:
  static constexpr uint8_t kObservedFlag = 1;
  static constexpr uint8_t kInsideFlag = 2;

  // Per voxel of plane z: observed enough (weight >= minimum) and inside (tsdf < 0).
  void classifyPlane(int z, std::vector<uint8_t>& flags) const {
    const int nx = volume_.side(0), ny = volume_.side(1);
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const int64_t i = volume_.index(x, y, z);
        flags[size_t(x) + size_t(nx) * size_t(y)] =
            uint8_t((volume_.valid(i) ? kObservedFlag : 0) | (volume_.tsdf(i) < 0.0f ? kInsideFlag : 0));
      }
  }

  uint32_t vertexOn(const Eigen::Vector3i& cell, const CellEdge& e) {
    const Eigen::Vector3i low = cell + cornerOffset(e.low);
    const uint64_t key = edgeKey(volume_.key(low.x(), low.y(), low.z()), e.dir);
    const auto found = local_.find(key);
    if (found != local_.end()) return found->second;
    const uint32_t id = static_cast<uint32_t>(out_->keys.size());
    local_.emplace(key, id);
    out_->keys.push_back(key);
    // Interpolate from the canonical (low -> high) endpoints so every cell computes the same vertex.
    const Eigen::Vector3i high = low + cornerOffset(e.dir);
    const float f0 = volume_.tsdf(volume_.index(low.x(), low.y(), low.z()));
    const float f1 = volume_.tsdf(volume_.index(high.x(), high.y(), high.z()));
    const float t = f0 / (f0 - f1);  // endpoints have opposite signs, so f0 != f1
    const Eigen::Vector3f pos = low.cast<float>() + t * (high - low).cast<float>();
    out_->vertices.push_back((pos + Eigen::Vector3f::Constant(0.5f)) * voxelSize_);
    Eigen::Vector3f n = (1.0f - t) * volume_.gradient(low) + t * volume_.gradient(high);
    if (n.squaredNorm() <= 0.0f) n = (f1 > f0 ? 1.0f : -1.0f) * (high - low).cast<float>();
    out_->normals.push_back(n.normalized());
    return id;
  }

  const VolumeSampler& volume_;
  float voxelSize_;
  SlabMesh* out_ = nullptr;
  std::unordered_map<uint64_t, uint32_t> local_;
};

void validate(const VolumeView& v) {
  if (v.data == nullptr) throw Error("extractMesh: the TSDF volume data pointer is null; pass the volume buffer");
  if (v.resolution < 2)
    throw Error("extractMesh: volume resolution " + std::to_string(v.resolution) +
                " is too small; it must be at least 2 voxels per side");
  if (!std::isfinite(v.size) || v.size <= 0.0f)
    throw Error("extractMesh: volume size " + std::to_string(v.size) + " m is invalid; it must be > 0");
  for (int a = 0; a < kAxes; ++a)
    if (v.offset[size_t(a)] < 0 || v.offset[size_t(a)] >= v.resolution)
      throw Error("extractMesh: cyclic offset " + std::to_string(v.offset[size_t(a)]) + " along axis " +
                  std::to_string(a) + " is outside [0, " + std::to_string(v.resolution) + ")");
  if (v.boxOnly && (v.extent[0] == 0 || v.offset != std::array<int, 3>{} || v.first != std::array<int, 3>{}))
    throw Error("extractMesh: a box stored alone (boxOnly) needs its extent, with offset and first 0");
  if (v.extent[0] != 0 || v.extent[1] != 0 || v.extent[2] != 0)
    for (int a = 0; a < kAxes; ++a)
      if (v.extent[size_t(a)] < 1 || v.first[size_t(a)] < 0 || v.first[size_t(a)] + v.extent[size_t(a)] > v.resolution)
        throw Error("extractMesh: box of " + std::to_string(v.extent[size_t(a)]) + " voxels from " +
                    std::to_string(v.first[size_t(a)]) + " along axis " + std::to_string(a) +
                    " is not inside the cube of " + std::to_string(v.resolution) + " (all extents 0: the whole cube)");
}

// Concatenates slabs in z order, mapping each slab's edges on its lower plane to the vertices the previous
// slab made there: the result equals a single serial sweep, whatever the thread count or the batches.
class SlabMerger {
 public:
  SlabMerger(int nx, int ny) : nx_(nx), ny_(ny) {}

  // Hands the vertices and triangles merged since the last call to `sink` (triangles index the whole mesh)
  // and forgets them; the edges shared with the next slab stay known.
  void flush(const MeshPieceSink& sink) {
    sink(mesh);
    emitted_ += mesh.vertices.size();
    mesh = Mesh{};
  }

  // Slab `s` (cells z in [s * kSlabCells, (s + 1) * kSlabCells)), after slab s - 1; released here.
  void append(SlabMesh& slab, int s) {
    const int z0 = s * kSlabCells;
    const int z1 = z0 + kSlabCells;
    std::unordered_map<uint64_t, uint32_t> top;
    std::vector<uint32_t> remap(slab.keys.size());
    for (size_t i = 0; i < slab.keys.size(); ++i) {
      const DecodedEdge e = decodeEdge(slab.keys[i], nx_, ny_);
      const bool inPlane = (e.dir & kZAxisBit) == 0;
      const auto shared = inPlane && e.low.z() == z0 ? previousTop_.find(slab.keys[i]) : previousTop_.end();
      if (shared != previousTop_.end()) {
        remap[i] = shared->second;
      } else {
        if (emitted_ + mesh.vertices.size() >= std::numeric_limits<uint32_t>::max())
          throw Error("extractMesh: more than 2^32 vertices; use a lower volume resolution");
        remap[i] = static_cast<uint32_t>(emitted_ + mesh.vertices.size());
        mesh.vertices.push_back(slab.vertices[i]);
        mesh.normals.push_back(slab.normals[i]);
      }
      if (inPlane && e.low.z() == z1) top.emplace(slab.keys[i], remap[i]);
    }
    for (const auto& tri : slab.triangles) mesh.triangles.push_back({remap[tri[0]], remap[tri[1]], remap[tri[2]]});
    previousTop_.swap(top);
    slab = SlabMesh{};  // release memory early
  }

  Mesh mesh;

 private:
  int nx_, ny_;
  size_t emitted_ = 0;                                  // vertices handed to a sink
  std::unordered_map<uint64_t, uint32_t> previousTop_;  // edges in the plane z = start of the next slab
};

// Slabs extracted at once per thread of the pool: the slabs' meshes held before they are merged stay a few
// per thread (not the whole volume's twice).
constexpr int kBatchSlabsPerThread = 2;

// Extracts in batches; with a sink, hands each batch's piece to it as soon as it is merged.
Mesh extract(const VolumeView& volume, const MeshOptions& options, ThreadPool& pool,
             const MeshPieceSink* sink) {
  validate(volume);
  const VolumeSampler sampler(volume, options.minWeight);
  const float voxelSize = volume.size / static_cast<float>(volume.resolution);
  const int cells = sampler.side(2) - 1;
  const int slabCount = ThreadPool::chunkCount(0, cells, kSlabCells);
  const int batch = kBatchSlabsPerThread * static_cast<int>(pool.threadCount());
  SlabMerger merger(sampler.side(0), sampler.side(1));
  std::vector<SlabMesh> slabs(static_cast<size_t>(std::min(batch, slabCount)));
  for (int first = 0; first < slabCount; first += batch) {
    const int last = std::min(slabCount, first + batch);
    pool.parallelFor(first, last, 1, [&](int, int begin, int end) {
      SlabExtractor extractor(sampler, voxelSize);
      for (int s = begin; s < end; ++s)
        extractor.run(s * kSlabCells, std::min(cells, (s + 1) * kSlabCells), slabs[size_t(s - first)]);
    });
    for (int s = first; s < last; ++s) merger.append(slabs[size_t(s - first)], s);
    if (sink) merger.flush(*sink);
  }
  return std::move(merger.mesh);
}

}  // namespace

Mesh extractMesh(const VolumeView& volume, const MeshOptions& options, ThreadPool& pool) {
  return extract(volume, options, pool, nullptr);
}

void extractMeshPieces(const VolumeView& volume, const MeshOptions& options, ThreadPool& pool,
                       const MeshPieceSink& sink) {
  extract(volume, options, pool, &sink);
}

Mesh extractMesh(const VolumeView& volume, const MeshOptions& options) {
  return extractMesh(volume, options, ThreadPool::global());
}

void transformMesh(Mesh& mesh, const Eigen::Isometry3f& T_volume_to_target) {
  for (auto& v : mesh.vertices) v = T_volume_to_target * v;
  const Eigen::Matrix3f rotation = T_volume_to_target.linear();
  for (auto& n : mesh.normals) n = rotation * n;
}

}  // namespace sb
