#include "navmap/nav_map.h"

#include <algorithm>
#include <chrono>
#include <filesystem>

#include "core/error.h"

namespace sb::navmap {

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}
std::vector<std::array<int32_t, 3>> occupiedCells(const VolumeVotes& votes, const NavMapConfig& config,
                                                  double voxelSizeM) {
  const double expected = voxelsPerVolumeCell(config, voxelSizeM);
  std::vector<std::array<int32_t, 3>> out;
  votes.forEach([&](int32_t x, int32_t y, int32_t z, const CellVotes& v) {
    if (classifyCell(v, config.minOccupiedVoxels, config.freeShare, expected) == CellState::occupied)
      out.push_back({x, y, z});
  });
  std::sort(out.begin(), out.end());  // the hash's order is not the run's
  return out;
}
}  // namespace

NavMap::NavMap(const NavMapConfig& config, double voxelSizeM, double muM)
    : config_(config.forVoxel(voxelSizeM)), voxelSizeM_(voxelSizeM), muM_(muM) {
  config_.validate(voxelSizeM);
  committed_ = std::make_unique<CommittedVotes>(config_, muM_);
}

bool NavMap::addCommitted(const VoxelBox& box) {
  if (!queueCommitted(box, nullptr, 0)) return false;
  committed_->drain();  // the caller's voxels are read before this returns
  return true;
}

bool NavMap::queueCommitted(const VoxelBox& box, std::shared_ptr<const void> owner, size_t bytes) {
  if (!frame_) return false;
  committed_->queue(box, frame_->T_world_to_map, std::move(owner), bytes);
  return true;
}

void NavMap::refreshLive(const VoxelBox& volume) {
  if (!frame_) return;
  const auto start = Clock::now();
  VoxelBox b = volume;
  b.muM = muM_;
  live_.clear();
  voteGrid(b, frame_->T_world_to_map, config_, live_);
  ++stats_.refreshes;
  stats_.refreshMs += msSince(start);
}

OccupancyImage NavMap::grid() const {
  committed_->drain();
  GridVotes all = committed_->grid();
  all.merge(live_);
  return gridImage(all, config_, voxelSizeM_);
}

OccupancyImage NavMap::write(const std::string& dir, const VoxelBox* volume) {
  if (!frame_) throw Error("navmap: no map frame (which way is up) to write '" + dir + "/map.pgm' in");
  const auto drainStart = Clock::now();
  committed_->drain();  // every slab handed over before is in the files
  stats_.writeMs += msSince(drainStart);
  if (volume) refreshLive(*volume);
  const auto start = Clock::now();
  OccupancyImage image = grid();
  writeGridFiles(dir, image, config_, *frame_);
  if (config_.octomapResolutionM > 0.0) {
    VolumeVotes cells = committed_->cells();
    if (volume) {
      VoxelBox b = *volume;
      b.muM = muM_;
      voteVolume(b, frame_->T_world_to_map, config_, cells);
    }
    surfaceCells_ = occupiedCells(cells, config_, voxelSizeM_);
    if (octomapAvailable())
      writeOctomap((std::filesystem::path(dir) / "map.bt").string(), cells, config_, voxelSizeM_, &stats_.octomap);
  }
  ++stats_.writes;
  stats_.writeMs += msSince(start);
  return image;
}

void NavMap::restore(const KeptVotes& kept) {
  frame_ = kept.frame;
  committed_->seed(kept.grid, kept.cells);
}

KeptVotes NavMap::kept(const VoxelBox* volume) const {
  if (!frame_) throw Error("navmap: no map frame to keep the map in");
  committed_->drain();
  KeptVotes out;
  out.frame = *frame_;
  out.grid = committed_->grid();
  out.cells = committed_->cells();
  if (volume) {
    VoxelBox b = *volume;
    b.muM = muM_;
    voteGrid(b, frame_->T_world_to_map, config_, out.grid);
    voteVolume(b, frame_->T_world_to_map, config_, out.cells);
  }
  return out;
}

NavMapStats NavMap::stats() const {
  NavMapStats s = stats_;
  const CommittedStats c = committed_->stats();
  s.slabs = c.boxes;
  s.slabMs = c.queueMs;
  s.slabWorkerMs = c.voteMs;
  s.slabWaitMs = c.waitMs;
  s.slabWaits = c.waits;
  s.gridBytes = c.gridBytes + live_.bytes();
  s.volumeCells = c.cells;
  return s;
}

}  // namespace sb::navmap
