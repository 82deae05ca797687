#pragma once
// A run's navigation map (issue 45) behind the run's map seam (runtime/map_sink.h): finds which way is up
// (the configured mount on the first frame, a floor fit on the first frames, or odometry through
// setFrameFromOdometry), reads the volume into the grid every NavMapConfig::updatePeriodFrames frames and
// each slab as it leaves (on NavMap's worker thread: the frame only hands the slab's shared copy over), and
// writes map.pgm, map.yaml, map_frame.json and map.bt (after the worker has voted every slab handed over).
//
//   auto map = std::make_shared<NavMapSink>(config, pipelineConfig, intrinsics, depthScale);
//   RunOutputs outputs; outputs.mapSink = map;   // Run calls onFrame, onSlab and, at the end, write

#include <memory>
#include <string>

#include "core/intrinsics.h"
#include "navmap/nav_map.h"
#include "pipeline/config.h"
#include "runtime/map_sink.h"

namespace sb::navmap {

// The voxels of `slab` the map takes (NavMap::addCommitted): all but the plane that stays in the volume (the
// slab holds it so the mesh is seamless; the volume counts it in the map), so a cell on the boundary is
// counted once.
VoxelBox slabBox(const VolumeSlab& slab);

class NavMapSink : public MapSink {
 public:
  // Throws sb::Error for a bad config (naming the key).
  NavMapSink(const NavMapConfig& config, const PipelineConfig& pipeline, const Intrinsics& intrinsics,
             double depthScale);

  void onFrame(const FrameRecord& record, const DepthFrame& frame, Pipeline& pipeline) override;
  void onSlab(std::shared_ptr<const VolumeSlab> slab) override;
  void write(const std::string& dir, Pipeline& pipeline) override;
  nlohmann::json summaryJson() const override;
  // The frame and the votes kept in a map store (navmap/kept_votes.h).
  std::vector<uint8_t> keptState(Pipeline& pipeline, bool final) override;
  bool keptStateChanged() const override;
  void restoreState(const std::vector<uint8_t>& payload, const std::string& path) override;

  // The hook for odometry (the fusion calls it with one frame's two poses, before or instead of a mount):
  // the map frame becomes the odometry frame (mapFrameFromOdometry). Ignored once a frame is set.
  void setFrameFromOdometry(const Eigen::Isometry3d& T_world_camera, const Eigen::Isometry3d& T_camera_to_odom);

  // Why there is no grid ("" when there is one or may still be).
  const std::string& why() const { return why_; }
  const NavMap& map() const { return map_; }
  // The grid now (every slab handed over; the live volume as of the last refresh).
  OccupancyImage grid() const { return map_.grid(); }

 private:
  void findUp(const FrameRecord& record, const DepthFrame& frame);
  VoxelBox volumeBox(Pipeline& pipeline) const;

  NavMap map_;
  Intrinsics intrinsics_;
  double depthScale_;
  int resolution_;
  size_t frames_ = 0;
  size_t slabsBeforeUp_ = 0;
  Eigen::Isometry3d firstPose_ = Eigen::Isometry3d::Identity();  // the floor fit's frame
  std::vector<Eigen::Vector3d> floorPoints_;                      // until the floor fit
  std::string why_;
  size_t slabsQueued_ = 0;           // handed to the map's worker
  size_t keptSlabs_ = 0;             // voted at the last keptState
  std::string restoredFrom_;         // the store's file the map continues from ("" when none)
};

}  // namespace sb::navmap
