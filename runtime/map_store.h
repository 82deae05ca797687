#pragma once
// The map kept on disk across runs (issue 55; docs/map-store.md): `slambooster run SEQ --map-store DIR`.
// A store directory holds
//   format.json        the format's name and version, and the voxel size and truncation its TSDF was made with
//   keyframes.bin      the relocaliser's keyframes: fern codes and poses in the store's frame
//   navmap.bin         the navigation map's frame and votes (navmap/kept_votes.h)
//   odometry.bin       the wheels' learnt calibration (runtime/kept_odometry.h)
//   slabs/slab-NNNNNN.tsdf  the TSDF that left the moving volume, and the final volume of each run, in the
//                      world's voxel grid, run-length coded (runtime/map_store_format.h)
// Every file is written aside and renamed over its name (core/atomic_file.h): a killed run leaves the store
// as of its last complete file. Opening checks every file (magic, version, size, checksum) and refuses a
// truncated, corrupt or foreign-version one, or a store made with another voxel size or truncation, naming the
// file; nothing of a refused store is overwritten.
//
// A new (or empty) store: the run maps as always and writes into the store as it goes; its frame is the
// run's. A kept store: the run starts localising (runtime/tracking_monitor.h, startInKeptMap): no frame is
// fused and none is `good` until the relocaliser confirms a view against the store's surface, placed for
// each candidate keyframe (placeFor); from then on every pose is in the store's frame, and slabs and keyframes
// go into the same store. A run never localised writes nothing into it (another building's store stays as it
// was). While writing, a shift that brings a part of the world back into the volume swaps the store's surface
// of it in (swapIn): a revisit tracks against the kept surface.
//
// In memory (MapStore::inMemory; docs/moving-volume.md, "Relocalising over the whole run"): an ordinary run with
// a moving volume and relocalisation keeps the slabs that leave the volume encoded the same way but in memory,
// bounded in bytes (the oldest dropped first), and writes no file: when the run is lost, the relocaliser's
// candidates anywhere on the run's map are tried against it (placeFor), and a shift back over kept space swaps
// it in (swapIn). It starts writing, has no kept keyframes, and its finish() keeps nothing.
//
// Threads: one thread (the run's) calls everything; a worker encodes and writes the slabs (the queue bounded
// in bytes like runtime/map_slabs.h's, the adding thread waits for room).

#include <Eigen/Geometry>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "pipeline/backend.h"
#include "pipeline/config.h"
#include "pipeline/volume_window.h"
#include "reloc/keyframe_database.h"
#include "runtime/map_store_bytes.h"
#include "runtime/map_store_format.h"

namespace sb {

struct Mesh;
class ThreadPool;

struct MapStoreOptions {
  // The slab files together at most this many bytes (the daemon's output.map_store_keep_mib; slambooster run
  // --map-store-keep-mib); past it the oldest go first, said in the log and the summary. 0: no limit.
  uint64_t keepSlabBytes = 0;
  size_t queueBytes = size_t(32) << 20;  // slab copies waiting for the worker, at most (one larger goes alone)
};

class MapStore {
 public:
  // Opens (or creates) the store `dir` for a run with `config` (a moving volume). Throws sb::Error naming the
  // file or key that is wrong, and what to do.
  MapStore(std::string dir, const PipelineConfig& config, const MapStoreOptions& options = {});
  // The slabs kept in memory only, at most `keepBytes` of them encoded (> 0; the oldest go first): no directory,
  // no file.
  static std::unique_ptr<MapStore> inMemory(const PipelineConfig& config, uint64_t keepBytes);
  ~MapStore();  // waits for the worker (a failure there is logged)
  MapStore(const MapStore&) = delete;
  MapStore& operator=(const MapStore&) = delete;

  // The store holds an earlier run's map: the run localises in it before it writes anything.
  bool kept() const { return !keptKeyframes_.empty(); }
  const std::vector<Keyframe>& keptKeyframes() const { return keptKeyframes_; }
  // Writing into the store: a new store from the first frame, a kept one once localised.
  bool writing() const { return writing_; }
  bool inMemory() const { return dir_.empty(); }
  void localised(size_t frame, double timestamp);

  // Places the volume for a relocalisation candidate at `pose` (the store's frame) and fills it with the
  // store's surface there (only when the placement changed). At most one new placement per frame (a few
  // hundred ms at 256^3): false, and nothing done, for a candidate that needs another one this frame.
  bool placeFor(const Eigen::Isometry3d& pose, VolumeWindow& window, BackendVolume& volume);
  void nextFrame() { placedThisFrame_ = false; }
  // Keeps the whole volume as a slab (the map that has not left it yet) and notes that the volume holds the
  // store's surface where it stands (the end of a run). Nothing unless writing.
  void keepVolume(const VolumeWindow& window, BackendVolume& volume);
  // Lost in the run (an in-run relocalisation): the volume holds the run's newest map where it stands, so a
  // candidate there needs no placement; the first placement keeps the whole volume (keepVolume) before it moves
  // it. A recovery that never leaves the volume keeps nothing. Nothing unless writing.
  void recoveryStarted(const VolumeWindow& window);
  // The box of the volume a shift brought in (VolumeWindow's enter listener): the store's surface of it
  // swapped back in (after the slabs still queued that meet it are written). Nothing unless writing; in memory,
  // nothing until a placement (an in-run relocalisation) has filled the volume from the kept slabs.
  void swapIn(const std::array<int, 3>& first, const std::array<int, 3>& extent, const VolumeWindow& window,
              BackendVolume& volume);
  // A slab that left the volume (VolumeWindow's slab listener): queued for the worker. Nothing unless writing.
  void addSlab(std::shared_ptr<const VolumeSlab> slab);
  // The payload of a state file (navmap.bin, odometry.bin) as the store held it when opened (checked then),
  // nullptr when it has none.
  const std::vector<uint8_t>* keptState(const mapstore::StateFile& file) const;
  // Its version (the payload's layout: from mapstore::kFormatVersion to file.version), 0 when it has none.
  uint32_t keptStateVersion(const mapstore::StateFile& file) const;
  std::string statePath(const mapstore::StateFile& file) const { return dir_ + "/" + file.name; }
  // Writes a state file (atomically). Nothing unless writing, in memory, or for an empty payload.
  void saveState(const mapstore::StateFile& file, const std::vector<uint8_t>& payload);
  // Rewrites keyframes.bin from the relocaliser's database (the store's kept keyframes were seeded into it).
  void saveKeyframes(const KeyframeDatabase& keyframes);
  // The end of a run: the final volume as a slab, the keyframes, every slab written. Nothing unless writing.
  void finish(const VolumeWindow& window, BackendVolume& volume, const KeyframeDatabase& keyframes);

  // The surface of every slab the store holds (every run's, this run's final volume among them once finish() has
  // kept it), in the store's frame (runtime/map_store_mesh.cpp): mesh.ply of a run writing a store. `slabsMeshed`:
  // how many slabs it covers.
  Mesh mesh(ThreadPool& pool, size_t* slabsMeshed = nullptr) const;

  // summary.json's "map_store": the directory, kept or new, localised (at which frame), files and bytes.
  nlohmann::json summaryJson() const;
  const std::string& dir() const { return dir_; }

 private:
  struct Entry {
    std::string path;  // the file, or in memory the slab's name for a message
    std::shared_ptr<const std::vector<uint8_t>> bytes;  // in memory: the encoded slab
    size_t number = 0;
    mapstore::SlabBox box;
    uint64_t size = 0;  // bytes
  };
  MapStore(const PipelineConfig& config, const MapStoreOptions& options);  // in memory
  void openExisting();
  void writeFormat() const;
  void loadBox(const mapstore::SlabBox& world, const VolumeWindow& window, BackendVolume& volume, bool cleared);
  void workerLoop();
  void writeSlab(const VolumeSlab& slab);  // on the worker
  // In memory (runtime/map_store_memory.cpp): an encoded slab kept (on the worker), the summary (mutex_ held).
  void keepSlab(const mapstore::SlabBox& box, const std::vector<uint8_t>& bytes, size_t number, const char* name);
  nlohmann::json inMemorySummaryLocked() const;
  void enforceRetentionLocked();
  void drain();
  bool pendingMeets(const mapstore::SlabBox& world) const;  // a slab queued or being written meets `world`

  std::string dir_;
  PipelineConfig config_;
  MapStoreOptions options_;
  std::vector<Keyframe> keptKeyframes_;
  bool writing_ = false;
  std::optional<size_t> localisedFrame_;
  double localisedStamp_ = 0.0;  // seconds, the frame's
  std::optional<Eigen::Vector3i> placedCorner_;  // the corner whose volume holds the store's surface
  bool placedThisFrame_ = false;
  bool volumeUnkept_ = false;  // lost in the run: the volume's map is to be kept before it moves
  size_t placements_ = 0, swapIns_ = 0, volumesKept_ = 0;
  double loadMs_ = 0.0;

  mutable std::mutex mutex_;
  std::condition_variable work_, room_;
  std::deque<std::shared_ptr<const VolumeSlab>> queue_;
  std::shared_ptr<const VolumeSlab> writingNow_;  // taken from the queue by the worker, not yet in slabs_
  size_t pending_ = 0, queuedBytes_ = 0;
  bool stop_ = false;
  std::exception_ptr error_;
  std::thread worker_;
  std::vector<Entry> slabs_;  // oldest first
  size_t nextNumber_ = 0;
  uint64_t slabBytes_ = 0, removedFiles_ = 0, removedBytes_ = 0;
  size_t keyframesSaved_ = 0;
  std::map<std::string, mapstore::StatePayload> keptStates_;  // state files at open: name -> payload
  std::map<std::string, uint64_t> savedStates_;              // state files written by this run: name -> bytes
  double workerMs_ = 0.0;
};

}  // namespace sb
