#pragma once
// The navigation map of a run (issue 45): the 2D occupancy grid of the robot's band and the 3D cells of
// map.bt, kept as the run goes. Voxels vote (navmap/voxel_votes.h) from two places only, never from a pass
// over the whole volume per frame:
//   - each slab that leaves the moving volume (queueCommitted: its votes are kept for good, cast on a worker
//     thread, navmap/committed_votes.h; the plane of the slab that stays in the volume is left to the volume,
//     so a cell on the boundary is counted once);
//   - the volume itself when the grid is written or published (the end of a run, the daemon's period;
//     refreshLive: its band's votes replace the previous ones), or every NavMapConfig::updatePeriodFrames.
// The grid is the sum of both. Memory: GridVotes' chunks (16 KiB per 3.2 m x 3.2 m of 5 cm cells explored)
// plus a hash of 3D cells (~40 bytes per observed cell of octomapResolutionM); map.bt's tree is built only
// while it is written.
//
// One thread (the SLAM thread) adds, refreshes, reads and writes; the committed votes' worker is internal, and
// every read (grid, write, stats) waits for it to have voted every slab queued before.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "navmap/committed_votes.h"
#include "navmap/grid_votes.h"
#include "navmap/kept_votes.h"
#include "navmap/map_files.h"
#include "navmap/map_frame.h"
#include "navmap/navmap_config.h"
#include "navmap/octomap_file.h"
#include "navmap/voxel_votes.h"

namespace sb::navmap {

struct NavMapStats {
  size_t slabs = 0, refreshes = 0, writes = 0;
  double slabMs = 0.0, refreshMs = 0.0, writeMs = 0.0;  // summed wall time (slabMs: the SLAM thread's hand-over)
  double slabWorkerMs = 0.0;  // the slabs' votes on the worker, summed
  double slabWaitMs = 0.0;    // of slabMs, waiting for room in the worker's queue
  size_t slabWaits = 0;
  size_t gridBytes = 0;       // the grid's votes (committed and live)
  size_t volumeCells = 0;     // 3D cells held (committed)
  OctomapStats octomap;       // of the last map.bt
};

class NavMap {
 public:
  // voxelSizeM and muM of the TSDF volume the votes come from. Throws sb::Error for a bad config.
  NavMap(const NavMapConfig& config, double voxelSizeM, double muM);

  void setFrame(const MapFrame& frame) { frame_ = frame; }
  const std::optional<MapFrame>& frame() const { return frame_; }

  // A box that left the volume for good, voted before this returns; ignored (false) before the frame is known.
  bool addCommitted(const VoxelBox& box);
  // The same, voted on the worker: `owner` keeps the box's voxels alive until then (`bytes` of them count in
  // the queue's bound; it waits while the queue is full). Ignored (false) before the frame is known.
  bool queueCommitted(const VoxelBox& box, std::shared_ptr<const void> owner, size_t bytes);
  // Waits until every box queued has voted (grid, write and stats do it first).
  void drain() const { committed_->drain(); }
  // The volume now: its band's votes replace the last refresh's.
  void refreshLive(const VoxelBox& volume);
  // The grid of every vote so far (committed, once the worker has voted them, and the last refresh).
  OccupancyImage grid() const;
  // DIR/map.pgm, map.yaml, map_frame.json and (with liboctomap and octomapResolutionM > 0) map.bt, each
  // atomically; `volume` (or nullptr) is refreshed first and adds its 3D cells to map.bt. Needs the frame.
  // Throws sb::Error naming a file.
  OccupancyImage write(const std::string& dir, const VoxelBox* volume);

  // An earlier run's map kept in a map store (navmap/kept_votes.h): its frame becomes this map's and its votes
  // are counted with the committed ones.
  void restore(const KeptVotes& kept);
  // The map's state to keep: the frame (needed) and every vote so far, committed and, with `volume`, the
  // volume's (read now; nullptr: the committed votes only, the volume's map is kept at the end). Waits for the
  // worker.
  KeptVotes kept(const VoxelBox* volume) const;

  const NavMapConfig& config() const { return config_; }
  NavMapStats stats() const;
  // The occupied 3D cells of the last write (map.bt's occupied leaves; the daemon's ?CLOUD): indices of
  // octomapResolutionM cells in the map frame, cell (i, j, k) centred at ((i, j, k) + 0.5) * resolution; sorted.
  // Empty with octomapResolutionM 0.
  const std::vector<std::array<int32_t, 3>>& surfaceCells() const { return surfaceCells_; }

 private:
  NavMapConfig config_;
  double voxelSizeM_, muM_;
  std::optional<MapFrame> frame_;
  std::unique_ptr<CommittedVotes> committed_;  // its worker's state: read after drain()
  GridVotes live_;
  NavMapStats stats_;
  std::vector<std::array<int32_t, 3>> surfaceCells_;
};

}  // namespace sb::navmap
