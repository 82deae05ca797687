#pragma once
// The grid as map_server reads it (issue 45): map.pgm (binary P5, 0 occupied, 254 free, 205 unknown, row 0
// the top: the highest y) and map.yaml (image, resolution, origin, negate, occupied_thresh, free_thresh), and
// map_frame.json (the map frame's transform from the SLAM world and where it came from). Each file whole or
// not at all (core/atomic_file.h: a temporary sibling renamed over the name).

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "navmap/grid_votes.h"
#include "navmap/map_frame.h"
#include "navmap/navmap_config.h"

namespace sb::navmap {

// A grid as nav_msgs/OccupancyGrid holds it: row-major from the cell at `origin`, row 0 the lowest y.
struct OccupancyImage {
  int width = 0, height = 0;
  double resolutionM = 0.05;
  Eigen::Vector2d originM = Eigen::Vector2d::Zero();  // map frame: the lower-left corner of cell (0, 0)
  std::vector<int8_t> cells;                          // -1 unknown, 0 free, 100 occupied
  int8_t at(int x, int y) const { return cells[size_t(y) * size_t(width) + size_t(x)]; }
  size_t count(CellState state) const;
};

// The cells of `votes` classified (classifyCell), over the bounds of the cells that have any vote.
OccupancyImage gridImage(const GridVotes& votes, const NavMapConfig& config, double voxelSizeM);

// map.pgm's bytes and map.yaml's text of `grid` (the PGM named `imageName` in the YAML).
std::string pgmBytes(const OccupancyImage& grid);
std::string yamlText(const OccupancyImage& grid, const NavMapConfig& config, const std::string& imageName);

// Writes DIR/map.pgm, DIR/map.yaml and DIR/map_frame.json atomically. Throws sb::Error naming the file.
void writeGridFiles(const std::string& dir, const OccupancyImage& grid, const NavMapConfig& config,
                    const MapFrame& frame);

}  // namespace sb::navmap
