#pragma once
// The navigation map's options of `slambooster run` (issue 45; navmap/): which way is up (a mount or a floor
// fit), the robot's band, the grid's and the OctoMap's resolution.

#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "drivers/frame_source.h"
#include "pipeline/config.h"
#include "runtime/map_sink.h"

namespace sb::cli {

struct NavMapOptions {
  std::string mount;  // "HEIGHT,PITCH,ROLL" (m, deg, deg)
  bool floor = false;
  std::string band;   // "MIN,MAX" (m)
  double resolution = 0.05;
  double octomapResolution = 0.1;
  int updatePeriod = 0;
};

void addNavMapOptions(CLI::App* sub, NavMapOptions& options);

// The run's map sink, or nullptr (and a line on the log saying why: nothing says which way is up). With
// `odometry` the sink is made even without a mount or a floor fit: the odometry's frame says which way is up.
// Throws sb::Error for a malformed option.
std::shared_ptr<MapSink> makeNavMapSink(const NavMapOptions& options, const PipelineConfig& pipeline,
                                        const SequenceInfo& info, bool odometry = false);

}  // namespace sb::cli
