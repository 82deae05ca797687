#include "navmap/nav_map_sink.h"

#include <spdlog/spdlog.h>

#include <filesystem>

namespace sb::navmap {

namespace {
constexpr int kFloorFitStridePx = 4;     // back-project every 4th pixel of every 4th row for the floor fit
constexpr size_t kFloorFitEveryFrames = 3;  // of the first floorFitFrames
}

NavMapSink::NavMapSink(const NavMapConfig& config, const PipelineConfig& pipeline, const Intrinsics& intrinsics,
                       double depthScale)
    : map_(config, double(pipeline.volumeSize) / pipeline.volumeResolution, pipeline.mu),
      intrinsics_(intrinsics),
      depthScale_(depthScale),
      resolution_(pipeline.volumeResolution) {
  if (config.up == "none")
    why_ = "no occupancy grid: nothing says which way is up (a handheld camera?); give the camera's mount "
           "(--map-mount HEIGHT,PITCH,ROLL) or --map-floor, or run with odometry";
}

void NavMapSink::setFrameFromOdometry(const Eigen::Isometry3d& T_world_camera,
                                      const Eigen::Isometry3d& T_camera_to_odom) {
  if (map_.frame()) return;
  map_.setFrame(mapFrameFromOdometry(T_world_camera, T_camera_to_odom));
  why_.clear();
  spdlog::info("navmap: map frame from odometry");
}

void NavMapSink::findUp(const FrameRecord& record, const DepthFrame& frame) {
  const NavMapConfig& c = map_.config();
  const Eigen::Isometry3d& pose = record.result.T_camera_to_world;
  if (c.up == "mount") {
    map_.setFrame(mapFrameFromMount(pose, CameraMount{c.mountHeightM, c.mountPitchDeg, c.mountRollDeg}));
    spdlog::info("navmap: map frame from the {}", map_.frame()->source);
    return;
  }
  if (c.up != "floor" || !why_.empty()) return;
  // The floor fit: points of every kFloorFitEveryFrames-th frame of the first floorFitFrames, in the first
  // frame's camera frame (a depth frame alone is too noisy at the floor's 2-4 m: a roll off by 3-4 deg on the
  // corridor drive; ten frames together: 0.0 deg), fitted once.
  if (frames_ == 1) firstPose_ = pose;
  if ((frames_ - 1) % kFloorFitEveryFrames == 0) {
    const Eigen::Isometry3d toFirst = firstPose_.inverse() * pose;
    const DepthRaw& depth = frame.depth;
    const double sx = double(intrinsics_.width) / depth.width(), sy = double(intrinsics_.height) / depth.height();
    const int phase = int(frames_ / kFloorFitEveryFrames);  // another sample of pixels per frame
    for (int v = phase % kFloorFitStridePx; v < depth.height(); v += kFloorFitStridePx)
      for (int u = (phase / kFloorFitStridePx) % kFloorFitStridePx; u < depth.width(); u += kFloorFitStridePx) {
        const double z = depth(u, v) / depthScale_;
        if (z <= 0.0) continue;
        floorPoints_.push_back(toFirst * Eigen::Vector3d((u * sx - intrinsics_.cx) / intrinsics_.fx * z,
                                                         (v * sy - intrinsics_.cy) / intrinsics_.fy * z, z));
      }
  }
  if (frames_ < size_t(c.floorFitFrames)) return;
  if (const std::optional<FloorFit> fit = fitFloor(floorPoints_)) {
    MapFrame f = mapFrameFromMount(firstPose_, fit->mount);
    f.source = "floor fit on the first " + std::to_string(frames_) + " frames: " + fit->describe();
    map_.setFrame(f);
    spdlog::info("navmap: map frame from the {}", f.source);
  } else {
    why_ = "no occupancy grid: no floor found in the first " + std::to_string(c.floorFitFrames) +
           " frames (a plane below the camera, tilted at most 30 deg); give the camera's mount instead";
    spdlog::warn("navmap: {}", why_);
  }
  std::vector<Eigen::Vector3d>().swap(floorPoints_);
}

VoxelBox NavMapSink::volumeBox(Pipeline& pipeline) const {
  VoxelBox box;
  box.data = pipeline.volumeData();
  box.dims = {resolution_, resolution_, resolution_};
  box.extent = box.dims;
  box.voxelSizeM = double(pipeline.config().volumeSize) / resolution_;
  if (const VolumeWindow* window = pipeline.volumeWindow()) {
    box.offset = window->offset();
    box.corner = window->cornerMetres();
  }
  return box;
}

void NavMapSink::onFrame(const FrameRecord& record, const DepthFrame& frame, Pipeline& pipeline) {
  ++frames_;
  // The robot's odometry says which way is up (its frame's z, REP 103), from the first good frame that has it.
  if (!map_.frame() && record.odometry.cameraToOdom && record.state == TrackingState::good)
    setFrameFromOdometry(record.result.T_camera_to_world, *record.odometry.cameraToOdom);
  if (!map_.frame()) findUp(record, frame);
  const int period = map_.config().updatePeriodFrames;
  if (map_.frame() && period > 0 && frames_ % size_t(period) == 0) map_.refreshLive(volumeBox(pipeline));
}

VoxelBox slabBox(const VolumeSlab& slab) {
  VoxelBox box;
  box.data = slab.voxels.data();
  box.dims = slab.extent;
  box.extent = slab.extent;
  box.corner = slab.corner;
  box.voxelSizeM = slab.voxelSize;
  // The slab holds the first plane that stays as well (pipeline/volume_window.cpp: a shift towards +axis
  // reads planes 0 .. leaving, towards -axis R - leaving - 1 .. R - 1); a whole volume that left has none.
  const size_t axis = size_t(slab.axis);
  if (slab.extent[axis] < slab.resolution && slab.extent[axis] > 1) {
    --box.extent[axis];
    if (slab.first[axis] != 0) box.first[axis] = 1;
  }
  return box;
}

void NavMapSink::onSlab(std::shared_ptr<const VolumeSlab> slab) {
  const VoxelBox box = slabBox(*slab);
  const size_t bytes = slab->bytes();
  if (!map_.queueCommitted(box, std::move(slab), bytes))
    ++slabsBeforeUp_;
  else
    ++slabsQueued_;
}

std::vector<uint8_t> NavMapSink::keptState(Pipeline& pipeline, bool final) {
  if (!map_.frame()) return {};
  const VoxelBox volume = volumeBox(pipeline);
  const KeptVotes kept = map_.kept(final ? &volume : nullptr);
  keptSlabs_ = map_.stats().slabs;
  return encodeKeptVotes(kept, map_.config());
}

bool NavMapSink::keptStateChanged() const {
  const size_t voted = map_.stats().slabs;  // never waits: the worker's count so far
  return map_.frame() && voted == slabsQueued_ && voted != keptSlabs_;
}

void NavMapSink::restoreState(const std::vector<uint8_t>& payload, const std::string& path) {
  KeptVotes kept = decodeKeptVotes(payload, path, map_.config());
  const std::string first = kept.frame.source;
  kept.frame.source = "the map store's (" + path + "), first from the " + first;
  if (first.rfind("the map store's", 0) == 0) kept.frame.source = first;  // kept through several runs: said once
  map_.restore(kept);
  restoredFrom_ = path;
  why_.clear();
  spdlog::info("navmap: the map frame and votes from '{}': the map continues in the store's frame", path);
}

void NavMapSink::write(const std::string& dir, Pipeline& pipeline) {
  if (!map_.frame()) {
    if (!why_.empty()) spdlog::warn("navmap: {}", why_);
    return;
  }
  const VoxelBox volume = volumeBox(pipeline);
  const OccupancyImage grid = map_.write(dir, &volume);
  spdlog::info("navmap: {}/map.pgm {}x{} cells of {} m: {} occupied, {} free", dir, grid.width, grid.height,
               grid.resolutionM, grid.count(CellState::occupied), grid.count(CellState::free));
}

nlohmann::json NavMapSink::summaryJson() const {
  const NavMapStats s = map_.stats();
  nlohmann::json j = {{"grid", bool(map_.frame())}};
  if (!map_.frame()) {
    j["why"] = why_.empty() ? "no map frame yet" : why_;
    return j;
  }
  j["up"] = map_.frame()->source;
  j["kept_map"] = restoredFrom_.empty() ? nlohmann::json(nullptr) : nlohmann::json(restoredFrom_);
  j["slabs"] = s.slabs;
  j["slabs_before_up"] = slabsBeforeUp_;
  j["refreshes"] = s.refreshes;
  j["slab_ms"] = s.slabMs;  // the SLAM thread's: handing the slabs over (waits for room included)
  j["slab_wait_ms"] = s.slabWaitMs;
  j["slab_worker_ms"] = s.slabWorkerMs;  // their votes, on the worker
  j["refresh_ms"] = s.refreshMs;
  j["upkeep_ms_per_frame"] = frames_ ? (s.slabMs + s.refreshMs) / double(frames_) : 0.0;
  j["write_ms"] = s.writeMs;
  j["grid_kib"] = double(s.gridBytes) / 1024.0;
  j["volume_cells"] = s.volumeCells;
  j["octomap"] = {{"available", octomapAvailable()},
                  {"occupied_leaves", s.octomap.occupiedLeaves},
                  {"free_leaves", s.octomap.freeLeaves},
                  {"tree_kib", double(s.octomap.treeBytes) / 1024.0}};
  return j;
}

}  // namespace sb::navmap
