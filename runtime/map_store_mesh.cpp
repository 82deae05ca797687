// The surface of everything a map store holds (runtime/map_store.h; issue 55): mesh.ply of a run that writes a
// store is every kept slab of every run (this run's final volume among them), in the store's frame, not only
// what this run's volume saw. The store's world voxel grid is meshed in chunks of kMeshChunkCells cells, each
// filled from the slabs that meet it as a placement is (oldest first: a newer slab's voxels win where two
// overlap), the chunks one voxel into each other so that every cell is meshed once.
#include "runtime/map_store.h"

#include <algorithm>
#include <chrono>
#include <limits>

#include "mesh/marching_cubes.h"

namespace sb {

namespace {

constexpr int kMeshChunkCells = 128;        // cells a side: a chunk of 129^3 voxels, 8.6 MB of TSDF
constexpr int16_t kUnobservedTsdf = 32767;  // kernels/volume.h: a cleared voxel is (+1, 0)

void append(Mesh& to, const Mesh& part) {
  const auto base = static_cast<uint32_t>(to.vertices.size());
  to.vertices.insert(to.vertices.end(), part.vertices.begin(), part.vertices.end());
  to.normals.insert(to.normals.end(), part.normals.begin(), part.normals.end());
  to.triangles.reserve(to.triangles.size() + part.triangles.size());
  for (const auto& t : part.triangles) to.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

}  // namespace

Mesh MapStore::mesh(ThreadPool& pool, size_t* slabsMeshed) const {
  std::vector<Entry> slabs;
  {
    std::lock_guard lock(mutex_);
    slabs = slabs_;
  }
  if (slabsMeshed) *slabsMeshed = slabs.size();
  Mesh out;
  if (slabs.empty()) return out;
  std::array<int, 3> lo{}, hi{};  // world voxels, hi past the last
  lo.fill(std::numeric_limits<int>::max());
  hi.fill(std::numeric_limits<int>::min());
  for (const Entry& e : slabs)
    for (size_t a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], e.box.first[a]);
      hi[a] = std::max(hi[a], e.box.first[a] + e.box.extent[a]);
    }
  const double voxel = config_.voxelSize();
  std::vector<int16_t> box;
  for (int z = lo[2]; z < hi[2]; z += kMeshChunkCells)
    for (int y = lo[1]; y < hi[1]; y += kMeshChunkCells)
      for (int x = lo[0]; x < hi[0]; x += kMeshChunkCells) {
        mapstore::SlabBox chunk;
        chunk.first = {x, y, z};
        for (size_t a = 0; a < 3; ++a) chunk.extent[a] = std::min(kMeshChunkCells + 1, hi[a] - chunk.first[a]);
        if (*std::min_element(chunk.extent.begin(), chunk.extent.end()) < 2) continue;  // no cell
        std::vector<const Entry*> meeting;  // oldest first
        for (const Entry& e : slabs)
          if (e.box.intersects(chunk)) meeting.push_back(&e);
        if (meeting.empty()) continue;
        box.assign(2 * chunk.voxels(), 0);
        for (size_t i = 0; i < box.size(); i += 2) box[i] = kUnobservedTsdf;
        for (const Entry* e : meeting) {
          if (e->bytes)
            mapstore::mergeSlab(*e->bytes, e->path, chunk, box.data());
          else
            mapstore::mergeSlab(e->path, chunk, box.data());
        }
        VolumeView view;
        view.data = box.data();
        view.resolution = *std::max_element(chunk.extent.begin(), chunk.extent.end());
        view.size = static_cast<float>(view.resolution * voxel);
        view.extent = chunk.extent;
        view.boxOnly = true;
        Mesh part = extractMesh(view, MeshOptions{}, pool);
        if (part.triangles.empty()) continue;
        const Eigen::Vector3f corner(float(x * voxel), float(y * voxel), float(z * voxel));
        transformMesh(part, Eigen::Isometry3f(Eigen::Translation3f(corner)));
        append(out, part);
      }
  return out;
}

}  // namespace sb
