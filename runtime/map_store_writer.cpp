// The map store's slab writer (runtime/map_store.h): the slabs that leave the volume queued (bounded in bytes),
// encoded and written by a worker thread (in memory: kept, runtime/map_store_memory.cpp), the store's bound on
// its slab bytes enforced oldest first.
#include "runtime/map_store.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "runtime/map_store_bytes.h"

namespace sb {

namespace fs = std::filesystem;

namespace {

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// The world voxel of a slab's first voxel (its corner is a whole number of voxels from the origin).
std::array<int, 3> worldVoxel(const Eigen::Vector3d& corner, double voxelSize) {
  std::array<int, 3> v{};
  for (int a = 0; a < 3; ++a) v[size_t(a)] = static_cast<int>(std::lround(corner[a] / voxelSize));
  return v;
}

}  // namespace

MapStore::~MapStore() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  work_.notify_all();
  if (worker_.joinable()) worker_.join();
  if (error_) {
    try {
      std::rethrow_exception(error_);
    } catch (const std::exception& e) {
      spdlog::error("map store: {}", e.what());
    }
  }
}

void MapStore::addSlab(std::shared_ptr<const VolumeSlab> slab) {
  if (!writing_ || !slab) return;
  std::unique_lock lock(mutex_);
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  const size_t bytes = slab->bytes();
  room_.wait(lock, [&] { return queuedBytes_ == 0 || queuedBytes_ + bytes <= options_.queueBytes; });
  queue_.push_back(std::move(slab));
  queuedBytes_ += bytes;
  ++pending_;
  if (!worker_.joinable()) worker_ = std::thread([this] { workerLoop(); });
  work_.notify_one();
}

bool MapStore::pendingMeets(const mapstore::SlabBox& world) const {
  const auto meets = [&](const VolumeSlab& slab) {
    mapstore::SlabBox box;
    box.first = worldVoxel(slab.corner, config_.voxelSize());
    box.extent = slab.extent;
    return box.intersects(world);
  };
  std::lock_guard lock(mutex_);
  if (writingNow_ && meets(*writingNow_)) return true;
  return std::any_of(queue_.begin(), queue_.end(), [&](const auto& slab) { return meets(*slab); });
}

void MapStore::drain() {
  std::unique_lock lock(mutex_);
  room_.wait(lock, [&] { return pending_ == 0; });
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

void MapStore::workerLoop() {
  for (;;) {
    std::shared_ptr<const VolumeSlab> slab;
    {
      std::unique_lock lock(mutex_);
      work_.wait(lock, [&] { return stop_ || !queue_.empty(); });
      if (queue_.empty()) return;
      slab = queue_.front();
      queue_.pop_front();
      writingNow_ = slab;
    }
    const auto start = std::chrono::steady_clock::now();
    try {
      writeSlab(*slab);
    } catch (...) {
      std::lock_guard lock(mutex_);
      if (!error_) error_ = std::current_exception();
    }
    std::lock_guard lock(mutex_);
    writingNow_.reset();
    workerMs_ += msSince(start);
    queuedBytes_ -= slab->bytes();
    --pending_;
    room_.notify_all();
  }
}

void MapStore::writeSlab(const VolumeSlab& slab) {
  mapstore::SlabBox box;
  box.first = worldVoxel(slab.corner, config_.voxelSize());
  box.extent = slab.extent;
  const std::vector<uint8_t> bytes = mapstore::encodeSlab(box, slab.voxels.data());
  if (bytes.empty()) return;  // nothing observed: nothing to keep
  size_t number;
  {
    std::lock_guard lock(mutex_);
    number = nextNumber_++;
  }
  char name[32];
  std::snprintf(name, sizeof name, "slab-%06zu.tsdf", number);
  if (inMemory()) {
    keepSlab(box, bytes, number, name);
    return;
  }
  const std::string path = dir_ + "/slabs/" + name;
  mapstore::writeFileBytes(path, bytes);
  std::lock_guard lock(mutex_);
  slabs_.push_back({path, nullptr, number, box, bytes.size()});
  slabBytes_ += bytes.size();
  enforceRetentionLocked();
}

void MapStore::enforceRetentionLocked() {
  while (options_.keepSlabBytes > 0 && slabBytes_ > options_.keepSlabBytes && slabs_.size() > 1) {
    const Entry oldest = slabs_.front();
    std::error_code ec;
    if (!oldest.bytes) fs::remove(oldest.path, ec);
    if (ec) {
      spdlog::warn("map store: cannot remove '{}' for the bound of {} MiB: {}", oldest.path,
                   options_.keepSlabBytes >> 20, ec.message());
      return;
    }
    if (oldest.bytes && removedFiles_ == 0)
      spdlog::info("map store: dropped the oldest kept slab ({} bytes), and from now on the oldest as needed: the "
                   "slabs kept in memory are bounded to {} MiB (relocalise_kept_map_mib)",
                   oldest.size, options_.keepSlabBytes >> 20);
    else if (!oldest.bytes)
      spdlog::info("map store: removed the oldest slab '{}' ({} bytes): the store's slabs are bounded to {} MiB",
                   oldest.path, oldest.size, options_.keepSlabBytes >> 20);
    slabs_.erase(slabs_.begin());
    slabBytes_ -= oldest.size;
    ++removedFiles_;
    removedBytes_ += oldest.size;
  }
}

}  // namespace sb
