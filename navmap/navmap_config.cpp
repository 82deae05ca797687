#include "navmap/navmap_config.h"

#include <cmath>

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
  if (updatePeriodFrames < 1) fail("update_period_frames", ">= 1");
  if (up != "none" && up != "mount" && up != "floor") fail("up", "none, mount or floor");
  if (up == "mount" && !(mountHeightM > 0.0 && mountHeightM < 10.0)) fail("mount_height_m", "(0, 10) m with up mount");
  if (std::abs(mountPitchDeg) > 90.0 || std::abs(mountRollDeg) > 90.0) fail("mount_pitch_deg/mount_roll_deg", "-90-90");
  if (floorFitFrames < 1) fail("floor_fit_frames", ">= 1");
}

}  // namespace sb::navmap
