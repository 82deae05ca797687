#pragma once
// The daemon's navigation map (issue 45; navmap/): a NavMapSink per pass from output.navmap's settings; every
// output.navmap_period_s the SLAM thread writes the pass's map.pgm, map.yaml, map_frame.json and map.bt
// (atomically) and publishes the grid, which ?MAP answers (daemon/protocol.h MapReport; with the map frame's
// pose and map.bt's path), and map.bt's occupied cells, which ?CLOUD answers, so a bridge never rebuilds them. SLAM thread only, but for the construction.

#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include "daemon/daemon_config.h"
#include "daemon/protocol.h"
#include "drivers/frame_source.h"
#include "navmap/nav_map_sink.h"
#include "pipeline/config.h"
#include "runtime/run.h"

namespace sb::daemon {

class MapPublisher {
 public:
  using Publish = std::function<void(MapReport)>;  // called on the SLAM thread; must not block

  // Reads the settings file output.navmap (throws sb::Error naming it and the key). `odometry`: the robot's
  // odometry may come (source.odometry not "none"); with "up": "none" it then says which way is up.
  MapPublisher(const OutputConfig& output, const PipelineConfig& pipeline, const SequenceInfo& sequence,
               bool odometry);
  void setPublish(Publish publish) { publish_ = std::move(publish); }

  // The sink of a new pass (nullptr and a log line saying why when nothing can say which way is up: "up":
  // "none" and no odometry; with odometry the grid starts at the first good frame that has it).
  std::shared_ptr<MapSink> startPass(uint32_t pass);
  // After each frame of the pass: at the period, the files and the grid.
  void afterFrame(Run& run, uint64_t frame);

 private:
  navmap::NavMapConfig settings_;
  std::chrono::duration<double> period_;
  PipelineConfig pipeline_;
  SequenceInfo sequence_;
  bool odometry_;
  Publish publish_;
  std::shared_ptr<navmap::NavMapSink> sink_;
  uint32_t pass_ = 0;
  std::chrono::steady_clock::time_point lastWrite_;
};

}  // namespace sb::daemon
