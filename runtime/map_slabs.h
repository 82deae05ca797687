#pragma once
// The whole run's map with a moving volume (issue 30): every slab that leaves the volume
// (pipeline/volume_window.h: a copy of its voxels, read before the shift clears them) is meshed and written
// by one worker thread (at nice +10: it takes the cores the SLAM thread leaves idle) to
// DIR/map_slabs/slab-NNNNNN.ply, a complete file (written aside, then renamed), so a
// killed run keeps the slabs written so far. The SLAM thread only queues the copy; the queue is bounded in
// bytes and, when full, the SLAM thread waits for room (no slab is ever dropped). At the end mesh.ply holds
// every slab kept and the final volume, in the world frame, once the worker has written every slab queued.
//
//   MapSlabs slabs(dir, MapSlabs::Options{});
//   window.setSlabListener([&](VolumeSlab&& slab) { slabs.add(std::move(slab)); });   // SLAM thread
//   ... slabs.writeMap(path, finalVolume);   // waits for the worker
//
// Not for several producers: one thread adds, drains and writes the map; the worker is internal.

#include <Eigen/Geometry>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/segment_store.h"
#include "core/unique_fd.h"
#include "core/thread_pool.h"
#include "mesh/marching_cubes.h"
#include "pipeline/pipeline.h"
#include "pipeline/volume_window.h"
#include "runtime/summary_sink.h"

namespace sb {

struct MapSlabsStats {
  double workerMs = 0.0;       // meshing and writing the slabs on the worker (wall time, summed)
  double waitMs = 0.0;         // the adding thread waiting for room in the queue, summed
  size_t waits = 0;            // adds that waited
  size_t peakQueuedBytes = 0;  // the most bytes of slab copies queued or being meshed at once
  size_t removedFiles = 0;     // slab files removed: by the retention limit (Options::keepBytes) or for space
  uint64_t removedBytes = 0;
  size_t removedForSpace = 0;  // of them, by the store's free-space floor or a full disk (Options::store)
};

// The queue's bound: 32 MiB of slab copies queued or being meshed (a 256^3 volume's slab of one 1.5 m shift,
// 81 planes of 256 KiB, is 20 MiB). A slab larger than the bound waits for the queue to be empty and goes
// alone, so the copies take at most max(bound, one slab).
constexpr size_t kMapSlabsQueueBytes = size_t(32) << 20;

struct MapSlabsOptions {
  size_t queueBytes = kMapSlabsQueueBytes;
  // Retention (the daemon's output.rotation.keep_slabs_mib): the slab files in DIR/map_slabs together at most
  // this many bytes; past it the oldest go first (the newest always stays). 0: no limit.
  uint64_t keepBytes = 0;
  // The retention of the directory's other outputs (the daemon's; core/segment_store.h), or nullptr (a
  // replay: a slab that finds the disk full fails). With it the slab files give way to its free-space floor
  // (min_free_mib) and to a full disk, oldest first among the slabs and the segments; the newest slab stays.
  // A slab write that finds the disk full removes the oldest of them and writes again.
  std::shared_ptr<SegmentStore> store;
};

class MapSlabs : private AttachedFiles {
 public:
  using Options = MapSlabsOptions;
  static constexpr size_t kDefaultQueueBytes = kMapSlabsQueueBytes;

  // Slabs go to `dir`/map_slabs (created at the first slab). Slab files already there (an earlier start of
  // the daemon) count in the retention, oldest first, and this run's are numbered on after them; they are not
  // part of this run's map. Throws sb::Error when that folder cannot be listed.
  explicit MapSlabs(std::string dir, const Options& options = Options{});
  // Writes every slab still queued, then stops the worker (a failure there is logged: finish() reports it).
  ~MapSlabs() override;
  MapSlabs(const MapSlabs&) = delete;
  MapSlabs& operator=(const MapSlabs&) = delete;

  // Queues `slab` for the worker; waits while the queue is full. Throws the sb::Error of a slab the worker
  // failed to write (naming the file) at the next add or drain. The shared copy may be held elsewhere too (the
  // navigation map's votes, runtime/map_sink.h): its bytes count here until this worker is done with it.
  void add(std::shared_ptr<const VolumeSlab> slab);
  void add(VolumeSlab&& slab) { add(std::make_shared<const VolumeSlab>(std::move(slab))); }
  void add(const VolumeSlab& slab) { add(VolumeSlab(slab)); }
  // Throws the sb::Error of a slab the worker failed to write, once (as add and drain do); returns at once
  // otherwise. The run asks after every frame: the first failed write ends the pass at that frame, not at
  // the next slab (issue 53 finding 8).
  void check();
  // Waits until every slab added is written (or found empty: a slab without surface writes no file).
  void drain();
  // Writes `path` from the slabs kept and `finalVolume` (world frame), after drain(); returns its triangles.
  size_t writeMap(const std::string& path, const Mesh& finalVolume);

  // This run's slab files kept, oldest first, and their triangles; after drain().
  const std::vector<std::string>& files();
  size_t triangles();
  MapSlabsStats stats() const;

 private:
  struct Written {
    std::string path;
    uint64_t bytes = 0;
    bool thisRun = true;
    int64_t order = 0;  // its age (SegmentStore::nowOrder)
  };
  // AttachedFiles (the store's free-space floor and full disk; any thread, with the store's lock held).
  std::optional<int64_t> oldestRemovable() const override;
  uint64_t removeOldestAttached() override;
  void listEarlier();  // in the constructor
  void workerLoop();
  void write(const VolumeSlab& slab, ThreadPool& serial);  // on the worker
  void openFolder();                                       // on the worker, at the first slab
  void removeOldestLocked();
  int removeSlabFile(const std::string& path) const;  // 0, or errno
  void enforceRetentionLocked();
  void rethrowLocked();

  std::string dir_;
  Options options_;
  std::thread worker_;  // started at the first slab
  mutable std::mutex mutex_;
  std::condition_variable work_, room_;
  std::deque<std::shared_ptr<const VolumeSlab>> queue_;
  size_t pending_ = 0;      // slabs queued or being written
  size_t queuedBytes_ = 0;  // their bytes
  bool stop_ = false;
  std::exception_ptr error_;     // the first failure not yet thrown
  UniqueFd folder_;              // dir_/map_slabs, never a symlink (opened at start or at the first slab)
  size_t firstNumber_ = 0;       // files are numbered firstNumber_ + shift
  std::deque<Written> written_;  // every slab file kept, oldest first (earlier starts' first)
  uint64_t writtenBytes_ = 0;
  uint64_t largestSlabBytes_ = 0;  // the largest slab file written (the worker's)
  std::vector<std::string> files_;  // this run's kept, refreshed by files()
  size_t triangles_ = 0;
  MapSlabsStats stats_;
};

// The slab files in `dir`/map_slabs now (STATUS "disk": a pass's, an earlier start's included).
struct MapSlabFiles {
  uint64_t bytes = 0;
  size_t files = 0;
};
MapSlabFiles mapSlabFiles(const std::string& dir);

// mesh.ply of a run (Run::finish): the final volume (read through a moving volume's cyclic offset and moved
// to the world frame) after every slab of `slabs` (nullptr or none: the volume alone, as a fixed volume
// always was); waits for `slabs`' worker first. Sets the summary's "mesh_triangles" (and "mesh_slabs").
// Throws sb::Error naming a file.
void writeRunMesh(const std::string& path, Pipeline& pipeline, MapSlabs* slabs, ThreadPool& pool,
                  SummarySink& summary);

// The summary's "moving_volume": shifts, their cost (ms), the final corner (world, metres); with `slabs`, the
// worker's share (slab_worker_ms, slab_wait_ms, slab_queue_peak_mib, slab_files_removed).
MovingVolumeSummary movingVolumeSummary(const VolumeWindow& window, const MapSlabs* slabs = nullptr);

// overviewPose (run.h) of the volume where it is now (the world frame when it never moved).
Eigen::Isometry3d movingVolumeOverview(Pipeline& pipeline);

}  // namespace sb
