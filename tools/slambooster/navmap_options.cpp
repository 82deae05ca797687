#include "tools/slambooster/navmap_options.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "navmap/nav_map_sink.h"

namespace sb::cli {

namespace {

// `count` finite numbers separated by commas (nan, inf and trailing text refused: issue 53).
std::vector<double> numbers(const std::string& text, size_t count, const std::string& option) {
  std::vector<double> out;
  std::stringstream in(text);
  std::string item;
  try {
    while (std::getline(in, item, ',')) {
      size_t used = 0;
      const double v = std::stod(item, &used);
      if (item.find_first_not_of(" \t", used) != std::string::npos || !std::isfinite(v)) throw Error("");
      out.push_back(v);
    }
  } catch (const std::exception&) {
    out.clear();
  }
  if (out.size() != count)
    throw Error(option + " '" + text + "': expected " + std::to_string(count) + " finite numbers separated by commas");
  return out;
}

void inRange(double v, double lo, double hi, bool open, const std::string& option, const std::string& text,
             const std::string& what) {
  if (open ? (v > lo && v < hi) : (v >= lo && v <= hi)) return;
  throw Error(option + " '" + text + "': " + what + " must lie in " + (open ? "(" : "[") + std::to_string(int(lo)) +
              ", " + std::to_string(int(hi)) + (open ? ")" : "]"));
}

}  // namespace

void addNavMapOptions(CLI::App* sub, NavMapOptions& o) {
  sub->add_option("--map-mount", o.mount,
                  "Navigation map (map.pgm, map.yaml, map.bt): the first camera's mount HEIGHT,PITCH,ROLL (metres\n"
                  "above the floor, degrees down, degrees about the optical axis); says which way is up");
  sub->add_flag("--map-floor", o.floor,
                "Navigation map: find which way is up from the floor in the first frames (a plane below the camera)");
  sub->add_option("--map-band", o.band, "Navigation map: the robot's height band MIN,MAX above the floor (m; 0.1,1.5)");
  sub->add_option("--map-resolution", o.resolution, "Navigation map: grid cell side (m)")->check(CLI::PositiveNumber);
  sub->add_option("--octomap-resolution", o.octomapResolution,
                  "map.bt leaf side (m; at least the volume's voxel; 0: no map.bt)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--map-update-frames", o.updatePeriod,
                  "Navigation map: re-read the volume every N frames (0: only at the end)")
      ->check(CLI::NonNegativeNumber);
}

std::shared_ptr<MapSink> makeNavMapSink(const NavMapOptions& o, const PipelineConfig& pipeline,
                                        const SequenceInfo& info, bool odometry) {
  navmap::NavMapConfig config;
  if (!o.mount.empty() && o.floor) throw Error("--map-mount and --map-floor: give one");
  if (!o.mount.empty()) {
    const std::vector<double> m = numbers(o.mount, 3, "--map-mount");
    inRange(m[0], 0.0, 10.0, true, "--map-mount", o.mount, "HEIGHT (metres above the floor)");
    inRange(m[1], -90.0, 90.0, false, "--map-mount", o.mount, "PITCH (degrees)");
    inRange(m[2], -90.0, 90.0, false, "--map-mount", o.mount, "ROLL (degrees)");
    config.up = "mount";
    config.mountHeightM = m[0], config.mountPitchDeg = m[1], config.mountRollDeg = m[2];
  } else if (o.floor) {
    config.up = "floor";
  }
  if (!o.band.empty()) {
    const std::vector<double> b = numbers(o.band, 2, "--map-band");
    config.bandMinM = b[0], config.bandMaxM = b[1];
  }
  config.resolutionM = o.resolution;
  config.octomapResolutionM = o.octomapResolution;
  config.updatePeriodFrames = o.updatePeriod;
  auto sink = std::make_shared<navmap::NavMapSink>(config, pipeline, info.intrinsics, info.depthScale);
  if (config.up == "none" && !odometry) {
    spdlog::warn("navmap: {}", sink->why());
    return nullptr;
  }
  return sink;
}

}  // namespace sb::cli
