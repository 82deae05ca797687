#pragma once
// The votes of the boxes that left the moving volume for good (issue 45), cast off the frame's path: the SLAM
// thread queues a slab (the copy the volume already made for the slab's mesh, shared, never copied again) and
// one worker thread votes it into the grid and the 3D cells, in the order queued. The SLAM thread reads the
// votes only after drain(), which waits for every box queued before it: the grid written at the end of a run
// or at the daemon's period holds every slab handed over before. The queue is bounded in bytes; when full the
// SLAM thread waits for room (no slab is dropped). Nothing is written to disk here: a crash loses what the
// map held in memory, as it did when the SLAM thread voted.
//
//   CommittedVotes votes(config, muM);
//   votes.queue(box, T_world_to_map, slabCopy, slabCopy->bytes());   // SLAM thread
//   votes.drain(); read votes.grid(), votes.cells();                   // SLAM thread
//
// One producer (the SLAM thread queues, drains and reads); the worker is internal.

#include <Eigen/Geometry>
#include <condition_variable>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>

#include "navmap/grid_votes.h"
#include "navmap/navmap_config.h"
#include "navmap/voxel_votes.h"

namespace sb::navmap {

// The queue's bound: 32 MiB of slab copies waiting for their votes (a 256^3 volume's 1.5 m slab is 20 MiB). A
// larger box waits for the queue to be empty and goes alone.
constexpr size_t kCommittedQueueBytes = size_t(32) << 20;

struct CommittedStats {
  size_t boxes = 0;      // voted
  double voteMs = 0.0;   // the worker's voting, summed (wall time)
  double queueMs = 0.0;  // the SLAM thread's hand-over, waits for room included, summed
  double waitMs = 0.0;   // of it, waiting for room
  size_t waits = 0;      // hand-overs that waited for room
  size_t cells = 0;      // 3D cells held
  size_t gridBytes = 0;  // the grid's votes
};

class CommittedVotes {
 public:
  CommittedVotes(const NavMapConfig& config, double muM, size_t queueBytes = kCommittedQueueBytes);
  // Stops the worker; what is still queued is dropped (nobody can read these votes any more).
  ~CommittedVotes();
  CommittedVotes(const CommittedVotes&) = delete;
  CommittedVotes& operator=(const CommittedVotes&) = delete;

  // Queues `box` (its voxels kept alive by `owner` until voted; `bytes` of them counted in the bound); waits
  // while the queue is full. Throws the worker's failure (bad_alloc) of an earlier box.
  void queue(const VoxelBox& box, const Eigen::Isometry3d& T_world_to_map, std::shared_ptr<const void> owner,
             size_t bytes);
  // Waits until every box queued has voted; throws the worker's failure, once.
  void drain();
  // The votes of every box voted; read after drain(), by the thread that queues.
  const GridVotes& grid() const { return grid_; }
  const VolumeVotes& cells() const { return cells_; }
  CommittedStats stats() const;
  // Adds an earlier run's votes (a map store, navmap/kept_votes.h) to the committed ones; waits for the worker
  // first. By the thread that queues.
  void seed(const GridVotes& grid, const VolumeVotes& cells);

 private:
  struct Job {
    VoxelBox box;
    Eigen::Isometry3d T_world_to_map;
    std::shared_ptr<const void> owner;
    size_t bytes = 0;
  };
  void workerLoop();

  const NavMapConfig config_;
  const double muM_;
  const size_t queueBytes_;
  std::thread worker_;  // started at the first box
  mutable std::mutex mutex_;
  std::condition_variable work_, done_;
  std::deque<Job> queue_;
  size_t pending_ = 0;      // boxes queued or being voted
  size_t queuedBytes_ = 0;  // their bytes
  bool stop_ = false;
  std::exception_ptr error_;
  GridVotes grid_;     // the worker's while pending_ > 0
  VolumeVotes cells_;  // likewise
  CommittedStats stats_;
};

}  // namespace sb::navmap
