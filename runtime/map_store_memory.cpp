// The map store in memory (MapStore::inMemory; runtime/map_store.h): an ordinary run's slabs that left the moving
// volume kept encoded in memory, bounded in bytes, for the relocaliser's candidates anywhere on the run's map. No
// directory, no file: what differs from the store on disk.
#include "runtime/map_store.h"

#include "core/error.h"

namespace sb {

MapStore::MapStore(const PipelineConfig& config, const MapStoreOptions& options) : config_(config), options_(options) {
  if (!config.movesVolume()) throw Error("map store in memory: needs the moving volume (volume_mode moving)");
  if (options.keepSlabBytes == 0) throw Error("map store in memory: needs a bound in bytes (> 0)");
  writing_ = true;
}

std::unique_ptr<MapStore> MapStore::inMemory(const PipelineConfig& config, uint64_t keepBytes) {
  MapStoreOptions options;
  options.keepSlabBytes = keepBytes;
  return std::unique_ptr<MapStore>(new MapStore(config, options));
}

void MapStore::keepSlab(const mapstore::SlabBox& box, const std::vector<uint8_t>& bytes, size_t number,
                        const char* name) {
  auto kept = std::make_shared<const std::vector<uint8_t>>(bytes);
  const uint64_t size = kept->size();
  std::lock_guard lock(mutex_);
  slabs_.push_back({std::string("kept slab ") + name, std::move(kept), number, box, size});
  slabBytes_ += size;
  enforceRetentionLocked();
}

nlohmann::json MapStore::inMemorySummaryLocked() const {
  return {{"in_memory", true},
          {"keep_bytes", options_.keepSlabBytes},
          {"slabs", slabs_.size()},
          {"slab_bytes", slabBytes_},
          {"slabs_dropped", removedFiles_},
          {"volumes_kept", volumesKept_},
          {"placements", placements_},
          {"swap_ins", swapIns_},
          {"load_ms", loadMs_},
          {"worker_ms", workerMs_}};
}

}  // namespace sb
