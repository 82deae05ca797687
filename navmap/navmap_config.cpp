#include "navmap/navmap_config.h"

#include <cmath>

#include "core/config_reader.h"
#include "core/error.h"

namespace sb::navmap {

void NavMapConfig::validate(double voxelSizeM) const {
  const auto fail = [](const std::string& key, const std::string& expected) {
    throw Error("navmap: '" + key + "' out of range: expected " + expected);
  };
  if (!(bandMinM >= 0.0 && bandMaxM > bandMinM && bandMaxM <= 10.0)) fail("band_m", "0 <= min < max <= 10 m");
  if (!(resolutionM >= 0.01 && resolutionM <= 1.0)) fail("resolution_m", "0.01-1 m");
  if (!(surfaceDepthM > 0.0)) fail("surface_depth_m", "> 0 m");
  if (minOccupiedVoxels < 1) fail("min_occupied_voxels", ">= 1");
  if (!(freeShare > 0.0 && freeShare <= 1.0)) fail("free_share", "(0, 1]");
  if (!(freeThresh >= 0.0 && occupiedThresh > freeThresh && occupiedThresh <= 1.0))
    fail("occupied_thresh/free_thresh", "0 <= free < occupied <= 1");
  if (octomapResolutionM != 0.0 && !(octomapResolutionM >= voxelSizeM * 0.999 && octomapResolutionM <= 2.0))
    fail("octomap_resolution_m", "0 (no map.bt) or the volume's voxel (" + std::to_string(voxelSizeM) + " m) to 2 m");
  if (updatePeriodFrames < 0) fail("update_period_frames", ">= 0 (0: only when written)");
  if (up != "none" && up != "mount" && up != "floor") fail("up", "none, mount or floor");
  if (up == "mount" && !(mountHeightM > 0.0 && mountHeightM < 10.0)) fail("mount_height_m", "(0, 10) m with up mount");
  // Written so that NaN fails too (issue 53: a NaN pitch gave a 0x0 map.pgm and null in map_frame.json).
  if (!(std::abs(mountPitchDeg) <= 90.0 && std::abs(mountRollDeg) <= 90.0))
    fail("mount_pitch_deg/mount_roll_deg", "-90-90");
  if (floorFitFrames < 1) fail("floor_fit_frames", ">= 1");
}

NavMapConfig NavMapConfig::forVoxel(double voxelSizeM) const {
  NavMapConfig c = *this;
  if (c.octomapResolutionM > 0.0 && c.octomapResolutionM < voxelSizeM) c.octomapResolutionM = voxelSizeM;
  return c;
}

void NavMapConfig::read(ConfigReader& r) {
  r.string("up", up, {"none", "mount", "floor"});
  r.number("mount_height_m", mountHeightM, 0.0, 10.0);
  r.number("mount_pitch_deg", mountPitchDeg, -90.0, 90.0);
  r.number("mount_roll_deg", mountRollDeg, -90.0, 90.0);
  r.integer("floor_fit_frames", floorFitFrames, 1, 10000);
  r.number("band_min_m", bandMinM, 0.0, 10.0);
  r.number("band_max_m", bandMaxM, 0.0, 10.0);
  r.number("resolution_m", resolutionM, 0.01, 1.0);
  r.number("surface_depth_m", surfaceDepthM, 0.001, 1.0);
  r.integer("min_occupied_voxels", minOccupiedVoxels, 1, 100000);
  r.number("free_share", freeShare, 0.001, 1.0);
  r.number("occupied_thresh", occupiedThresh, 0.0, 1.0);
  r.number("free_thresh", freeThresh, 0.0, 1.0);
  r.number("octomap_resolution_m", octomapResolutionM, 0.0, 2.0);
  r.integer("update_period_frames", updatePeriodFrames, 0, 100000);
  r.finish();
}

nlohmann::json NavMapConfig::toJson() const {
  return {{"up", up},
          {"mount_height_m", mountHeightM},
          {"mount_pitch_deg", mountPitchDeg},
          {"mount_roll_deg", mountRollDeg},
          {"floor_fit_frames", floorFitFrames},
          {"band_min_m", bandMinM},
          {"band_max_m", bandMaxM},
          {"resolution_m", resolutionM},
          {"surface_depth_m", surfaceDepthM},
          {"min_occupied_voxels", minOccupiedVoxels},
          {"free_share", freeShare},
          {"occupied_thresh", occupiedThresh},
          {"free_thresh", freeThresh},
          {"octomap_resolution_m", octomapResolutionM},
          {"update_period_frames", updatePeriodFrames}};
}

NavMapConfig loadNavMapConfig(const std::string& path) {
  const nlohmann::json j = readJsonConfig(path, "navigation map settings");
  ConfigReader r(j, path);
  NavMapConfig c;
  c.read(r);
  return c;
}

}  // namespace sb::navmap
