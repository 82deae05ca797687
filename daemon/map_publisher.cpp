#include "daemon/map_publisher.h"

#include <spdlog/spdlog.h>

#include <filesystem>

#include "core/error.h"
#include "navmap/octomap_file.h"

namespace sb::daemon {

MapPublisher::MapPublisher(const OutputConfig& output, const PipelineConfig& pipeline, const SequenceInfo& sequence,
                           bool odometry)
    : settings_(navmap::loadNavMapConfig(output.navmap).forVoxel(double(pipeline.volumeSize) /
                                                                  pipeline.volumeResolution)),
      period_(output.navmapPeriodS),
      pipeline_(pipeline),
      sequence_(sequence),
      odometry_(odometry) {
  settings_.validate(double(pipeline.volumeSize) / pipeline.volumeResolution);
}

std::shared_ptr<MapSink> MapPublisher::startPass(uint32_t pass) {
  pass_ = pass;
  sink_ = std::make_shared<navmap::NavMapSink>(settings_, pipeline_, sequence_.intrinsics, sequence_.depthScale);
  lastWrite_ = std::chrono::steady_clock::now();
  if (settings_.up == "none" && !odometry_) {
    spdlog::warn("navmap: {}", sink_->why());
    sink_.reset();
  } else if (settings_.up == "none") {
    spdlog::info("navmap: up from the robot's odometry, at the first good frame that has it");
  }
  return sink_;
}

void MapPublisher::afterFrame(Run& run, uint64_t frame) {
  if (!sink_ || !sink_->map().frame()) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - lastWrite_ < period_) return;
  lastWrite_ = now;
  try {
    sink_->write(run.dir(), run.pipeline());  // atomically: a reader never sees half a map
  } catch (const Error& e) {
    spdlog::warn("navmap: {}", e.what());  // the next period tries again; the run goes on
  }
  if (!publish_) return;
  const navmap::OccupancyImage grid = sink_->grid();
  MapReport report;
  report.pass = pass_;
  report.frame = frame;
  report.width = grid.width;
  report.height = grid.height;
  report.resolutionM = grid.resolutionM;
  report.originX = grid.originM.x();
  report.originY = grid.originM.y();
  report.up = sink_->map().frame()->source;
  report.cells = grid.cells;
  const Eigen::Isometry3d T_map_to_world = sink_->map().frame()->T_world_to_map.inverse();
  const Eigen::Quaterniond q(T_map_to_world.rotation());
  report.framePosition = {T_map_to_world.translation().x(), T_map_to_world.translation().y(),
                          T_map_to_world.translation().z()};
  report.frameQuaternion = {q.x(), q.y(), q.z(), q.w()};
  if (settings_.octomapResolutionM > 0.0) {
    if (navmap::octomapAvailable()) report.octomap = std::filesystem::absolute(run.dir() + "/map.bt").string();
    report.cloudResolutionM = settings_.octomapResolutionM;
    report.cloud = sink_->map().surfaceCells();
    boundCloud(report, kMaxCloudCells);
  }
  publish_(std::move(report));
}

}  // namespace sb::daemon
