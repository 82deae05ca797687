// The map store and the moving volume (runtime/map_store.h): the volume placed and filled from the kept slabs
// for a relocalisation candidate, the kept surface swapped back in where a shift brings the volume, and the
// volume kept whole as a slab (a recovery's first placement, the end of a run).
#include "runtime/map_store.h"

#include <chrono>

namespace sb {

namespace {

constexpr int16_t kUnobservedTsdf = 32767;  // kernels/volume.h: a cleared voxel is (+1, 0)

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

void MapStore::loadBox(const mapstore::SlabBox& world, const VolumeWindow& window, BackendVolume& volume,
                       bool cleared) {
  const auto start = std::chrono::steady_clock::now();
  std::array<int, 3> first{};
  for (int a = 0; a < 3; ++a) first[size_t(a)] = world.first[a] - window.cornerVoxels()[a];
  std::vector<Entry> meeting;  // oldest first: a newer slab's voxels win where two overlap
  {
    std::lock_guard lock(mutex_);
    for (const Entry& e : slabs_)
      if (e.box.intersects(world)) meeting.push_back(e);
  }
  if (meeting.empty()) {
    loadMs_ += msSince(start);
    return;
  }
  std::vector<int16_t> box(2 * world.voxels());
  if (cleared) {
    for (size_t i = 0; i < box.size(); i += 2) box[i] = kUnobservedTsdf, box[i + 1] = 0;
  } else {
    volume.readVolumeBox(first, world.extent, box.data());
  }
  for (const Entry& e : meeting) {
    if (e.bytes)
      mapstore::mergeSlab(*e.bytes, e.path, world, box.data());
    else
      mapstore::mergeSlab(e.path, world, box.data());
  }
  volume.writeVolumeBox(first, world.extent, box.data());
  loadMs_ += msSince(start);
}

bool MapStore::placeFor(const Eigen::Isometry3d& pose, VolumeWindow& window, BackendVolume& volume) {
  if (placedCorner_ && *placedCorner_ == window.cornerVoxels() && window.shiftFor(pose, window.cornerVoxels()).isZero())
    return true;  // placed already
  if (placedThisFrame_) return false;
  placedThisFrame_ = true;
  if (volumeUnkept_) {
    keepVolume(window, volume);
    volumeUnkept_ = false;
  }
  drain();  // the slabs still queued (an in-run relocalisation's whole volume) are kept before the volume moves
  window.placeFor(pose, volume);
  if (placedCorner_ && *placedCorner_ == window.cornerVoxels()) return true;
  const int r = config_.volumeResolution;
  mapstore::SlabBox world;
  for (int a = 0; a < 3; ++a) world.first[size_t(a)] = window.cornerVoxels()[a];
  world.extent = {r, r, r};
  // Nothing is fused while localising: the volume holds the store's surface only (what stayed in it from an
  // earlier placement, the rest cleared by the move), so it is written whole from the store.
  loadBox(world, window, volume, /*cleared=*/true);
  placedCorner_ = window.cornerVoxels();
  ++placements_;
  return true;
}

void MapStore::swapIn(const std::array<int, 3>& first, const std::array<int, 3>& extent, const VolumeWindow& window,
                      BackendVolume& volume) {
  if (!writing_) return;
  // In memory, only once a relocalisation has placed the volume from the kept slabs: until then the run maps as
  // one without them (the same poses, byte for byte), and a revisit is tracked against what the volume holds.
  if (inMemory() && placements_ == 0) return;
  mapstore::SlabBox world;
  for (int a = 0; a < 3; ++a) world.first[size_t(a)] = first[size_t(a)] + window.cornerVoxels()[a];
  world.extent = extent;
  // A slab that left and meets the box is kept before the volume comes back over it. Only then: the slab that
  // left with this shift lies on the other side of the volume, and its encoding goes on beside the run.
  if (pendingMeets(world)) drain();
  loadBox(world, window, volume, /*cleared=*/false);
  ++swapIns_;
}

void MapStore::keepVolume(const VolumeWindow& window, BackendVolume& volume) {
  if (!writing_) return;
  const int r = config_.volumeResolution;
  auto slab = std::make_shared<VolumeSlab>();
  slab->resolution = r;
  slab->extent = {r, r, r};
  slab->voxels.resize(2 * size_t(r) * size_t(r) * size_t(r));
  volume.readVolumeBox(slab->first, slab->extent, slab->voxels.data());
  slab->corner = window.cornerMetres();
  slab->voxelSize = config_.voxelSize();
  addSlab(std::move(slab));
  placedCorner_ = window.cornerVoxels();
  ++volumesKept_;
}

void MapStore::recoveryStarted(const VolumeWindow& window) {
  if (!writing_) return;
  placedCorner_ = window.cornerVoxels();
  volumeUnkept_ = true;
}

void MapStore::finish(const VolumeWindow& window, BackendVolume& volume, const KeyframeDatabase& keyframes) {
  if (!writing_ || inMemory()) return;  // in memory: kept for this run only
  keepVolume(window, volume);
  drain();
  saveKeyframes(keyframes);
}

}  // namespace sb
