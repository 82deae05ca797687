#include "navmap/map_files.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "navmap/voxel_votes.h"

namespace sb::navmap {

namespace {

constexpr uint8_t kPgmOccupied = 0, kPgmFree = 254, kPgmUnknown = 205;  // map_server's trinary values

void writeText(const std::string& path, const std::string& bytes) {
  writeFileAtomically(path, [&](std::FILE* file, const std::string& temporary) {
    if (std::fwrite(bytes.data(), 1, bytes.size(), file) != bytes.size())
      throw Error("cannot write '" + temporary + "' (check the disk and its permissions)");
  });
}

}  // namespace

size_t OccupancyImage::count(CellState state) const {
  size_t n = 0;
  for (int8_t c : cells) n += c == int8_t(state);
  return n;
}

OccupancyImage gridImage(const GridVotes& votes, const NavMapConfig& config, double voxelSizeM) {
  OccupancyImage image;
  image.resolutionM = config.resolutionM;
  int64_t minX = 0, minY = 0, maxX = -1, maxY = -1;
  if (!votes.bounds(minX, minY, maxX, maxY)) return image;
  image.width = int(maxX - minX + 1), image.height = int(maxY - minY + 1);
  image.originM = Eigen::Vector2d(double(minX), double(minY)) * config.resolutionM;
  image.cells.assign(size_t(image.width) * size_t(image.height), int8_t(CellState::unknown));
  const double expected = bandVoxelsPerCell(config, voxelSizeM);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      image.cells[size_t(y) * size_t(image.width) + size_t(x)] = int8_t(
          classifyCell(votes.get(minX + x, minY + y), config.minOccupiedVoxels, config.freeShare, expected));
  return image;
}

std::string pgmBytes(const OccupancyImage& grid) {
  std::string out = "P5\n# slambooster navmap\n" + std::to_string(grid.width) + " " + std::to_string(grid.height) +
                    "\n255\n";
  const size_t header = out.size();
  out.resize(header + size_t(grid.width) * size_t(grid.height));
  for (int row = 0; row < grid.height; ++row) {
    const int y = grid.height - 1 - row;  // row 0 of the image is the top: the highest y
    for (int x = 0; x < grid.width; ++x) {
      const int8_t c = grid.at(x, y);
      out[header + size_t(row) * size_t(grid.width) + size_t(x)] =
          char(c == int8_t(CellState::occupied) ? kPgmOccupied : c == int8_t(CellState::free) ? kPgmFree : kPgmUnknown);
    }
  }
  return out;
}

std::string yamlText(const OccupancyImage& grid, const NavMapConfig& config, const std::string& imageName) {
  char text[512];
  std::snprintf(text, sizeof text,
                "image: %s\nresolution: %.6f\norigin: [%.6f, %.6f, 0.0]\nnegate: 0\noccupied_thresh: %.3f\n"
                "free_thresh: %.3f\n",
                imageName.c_str(), grid.resolutionM, grid.originM.x(), grid.originM.y(), config.occupiedThresh,
                config.freeThresh);
  return text;
}

void writeGridFiles(const std::string& dir, const OccupancyImage& grid, const NavMapConfig& config,
                    const MapFrame& frame) {
  const std::filesystem::path out(dir);
  writeText((out / "map.pgm").string(), pgmBytes(grid));
  writeText((out / "map.yaml").string(), yamlText(grid, config, "map.pgm"));
  nlohmann::json rows = nlohmann::json::array();
  const Eigen::Matrix4d m = frame.T_world_to_map.matrix();
  for (int r = 0; r < 4; ++r) rows.push_back({m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
  const nlohmann::json j = {{"T_world_to_map", rows},
                            {"source", frame.source},
                            {"band_m", {config.bandMinM, config.bandMaxM}},
                            {"resolution_m", grid.resolutionM},
                            {"occupied_cells", grid.count(CellState::occupied)},
                            {"free_cells", grid.count(CellState::free)}};
  writeText((out / "map_frame.json").string(), j.dump(2) + "\n");
}

}  // namespace sb::navmap
