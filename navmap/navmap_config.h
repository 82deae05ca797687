#pragma once
// The navigation map's settings (issue 45; config/README.md "navmap"): the robot's height band, the grid's
// cells, when a voxel is surface or free, the OctoMap's resolution and how often the grid follows the volume.

#include <nlohmann/json.hpp>
#include <string>

namespace sb {
class ConfigReader;
}

namespace sb::navmap {

struct NavMapConfig {
  double bandMinM = 0.1;        // the robot's height band above the floor, metres: surface in it is an obstacle
  double bandMaxM = 1.5;
  double resolutionM = 0.05;    // the grid's cell side, metres (map.yaml "resolution")
  double surfaceDepthM = 0.05;  // a voxel is surface when observed and at most this behind the surface, metres
  int minOccupiedVoxels = 2;    // surface voxels in a cell's band (or a 3D cell) that make it occupied
  double freeShare = 0.3;       // of a cell's band voxels, observed in front of any surface: the cell is free
  double occupiedThresh = 0.65;  // map.yaml (map_server's meaning)
  double freeThresh = 0.196;     // map.yaml
  double octomapResolutionM = 0.1;  // map.bt's leaf side, metres (raised to the volume's voxel); 0: no map.bt
  // The live volume's share of the grid is re-read every this many frames; 0 (default): only when the grid is
  // written or published (the end of a run, the daemon's period): a read of the volume's band costs ~80 ms at
  // 256^3 and 2 cm voxels, 3 ms per frame at 30.
  int updatePeriodFrames = 0;
  // Which way is up when no odometry says it: "none" (no grid: a handheld camera), "mount" (the keys below),
  // "floor" (a floor fit on the first frames).
  std::string up = "none";
  double mountHeightM = 0.0;   // the first camera's optical centre above the floor, metres
  double mountPitchDeg = 0.0;  // its optical axis below the horizon, degrees
  double mountRollDeg = 0.0;   // about the optical axis, degrees
  int floorFitFrames = 30;     // "floor": fitted once on every third of the first this many frames together

  // Throws sb::Error naming the key for a value out of range.
  void validate(double voxelSizeM) const;
  // The settings for a volume of this voxel: map.bt's leaves no finer than a voxel (the default 0.1 m on a
  // coarse volume, e.g. 64^3 over 7.5 m, is raised to the voxel instead of failing a run that never asked for
  // a map: with odometry the grid is made by itself).
  NavMapConfig forVoxel(double voxelSizeM) const;
  // config/navmap.json's keys (config/README.md "navmap"); read throws sb::Error naming the file and key.
  void read(ConfigReader& r);
  nlohmann::json toJson() const;
};

// The settings file `path` (config/navmap.json keys). Throws sb::Error naming the file and key.
NavMapConfig loadNavMapConfig(const std::string& path);

}  // namespace sb::navmap
