// map_server's files against a hand-made grid, and map.bt read back by liboctomap.
#include <catch2/catch.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "navmap/map_files.h"
#include "navmap/nav_map.h"
#include "tests/navmap/tsdf_scene.h"
#include "tests/support/test_data.h"

#ifdef SB_HAVE_OCTOMAP
#include <octomap/OcTree.h>
#endif

using namespace sb::navmap;

namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A wall facing the camera at world z = 3 (map x = 2.5) over a floor at world y = 2.2 (map z = 0), 4 cm voxels.
sb::navmap::test::TsdfScene wallScene() {
  return sb::navmap::test::TsdfScene(
      [](const Eigen::Vector3d& w) { return std::min(2.2 - w.y(), 3.0 - w.z()); }, 100, 0.04);
}

// The scene's map with 8 cm map.bt cells, its frame from a level camera 1.2 m up at (2, 1, 0.5).
std::unique_ptr<NavMap> wallMap(const sb::navmap::test::TsdfScene& scene) {
  NavMapConfig config;
  config.octomapResolutionM = 0.08;
  auto map = std::make_unique<NavMap>(config, scene.voxel, scene.mu);
  Eigen::Isometry3d camera = Eigen::Isometry3d::Identity();
  camera.translation() = Eigen::Vector3d(2.0, 1.0, 0.5);
  map->setFrame(mapFrameFromMount(camera, CameraMount{1.2, 0.0, 0.0}));
  return map;
}

}  // namespace

TEST_CASE("map.pgm and map.yaml of a hand-made grid", "[navmap]") {
  // 3 x 2 cells: the bottom row (y = 0) occupied, free, unknown; the top row free, unknown, occupied.
  OccupancyImage g;
  g.width = 3, g.height = 2, g.resolutionM = 0.05;
  g.originM = Eigen::Vector2d(-1.25, 0.5);
  g.cells = {100, 0, -1, 0, -1, 100};
  // Row 0 of the image is the top (y = 1): 254 205 0, then 0 254 205.
  const std::string expected = std::string("P5\n# slambooster navmap\n3 2\n255\n") +
                               std::string("\xfe\xcd\x00\x00\xfe\xcd", 6);
  CHECK(pgmBytes(g) == expected);
  CHECK(yamlText(g, NavMapConfig{}, "map.pgm") ==
        "image: map.pgm\nresolution: 0.050000\norigin: [-1.250000, 0.500000, 0.0]\nnegate: 0\n"
        "occupied_thresh: 0.650\nfree_thresh: 0.196\n");
  const std::string dir = sb::test::scratchDir("navmap_files");
  MapFrame frame;
  frame.source = "mount: test";
  writeGridFiles(dir, g, NavMapConfig{}, frame);
  CHECK(slurp(dir + "/map.pgm") == expected);
  CHECK(slurp(dir + "/map.yaml").rfind("image: map.pgm\n", 0) == 0);
  CHECK(slurp(dir + "/map_frame.json").find("\"occupied_cells\": 2") != std::string::npos);
  CHECK(!std::filesystem::exists(dir + "/map.pgm.tmp"));
}

TEST_CASE("map.bt loads with liboctomap: the wall occupied, the room free", "[navmap]") {
  if (!octomapAvailable()) {
    WARN("built without liboctomap: no map.bt");
    return;
  }
  const auto scene = wallScene();
  const std::unique_ptr<NavMap> owned = wallMap(scene);
  NavMap& map = *owned;
  const std::string dir = sb::test::scratchDir("navmap_octomap");
  const VoxelBox volume = scene.box();
  map.write(dir, &volume);
  CHECK(map.stats().octomap.occupiedLeaves > 0);
#ifdef SB_HAVE_OCTOMAP
  octomap::OcTree tree(0.1);
  REQUIRE(tree.readBinary(dir + "/map.bt"));
  CHECK(tree.getResolution() == Approx(0.08));
  const octomap::OcTreeNode* wall = tree.search(2.52, 0.0, 0.8);
  REQUIRE(wall);
  CHECK(tree.isNodeOccupied(wall));
  const octomap::OcTreeNode* room = tree.search(1.0, 0.0, 0.8);
  REQUIRE(room);
  CHECK(!tree.isNodeOccupied(room));
#endif
}

TEST_CASE("the surface cells (the daemon's cloud) are map.bt's occupied cells, with or without liboctomap",
          "[navmap]") {
  const auto scene = wallScene();
  const std::unique_ptr<NavMap> owned = wallMap(scene);
  NavMap& map = *owned;
  CHECK(map.surfaceCells().empty());  // nothing before the first write
  const VoxelBox volume = scene.box();
  map.write(sb::test::scratchDir("navmap_surface"), &volume);
  const auto& cells = map.surfaceCells();
  REQUIRE(!cells.empty());
  CHECK(std::is_sorted(cells.begin(), cells.end()));
  const auto has = [&](double x, double y, double z) {  // the cell holding map point (x, y, z)
    const std::array<int32_t, 3> c{int32_t(std::floor(x / 0.08)), int32_t(std::floor(y / 0.08)),
                                   int32_t(std::floor(z / 0.08))};
    return std::binary_search(cells.begin(), cells.end(), c);
  };
  CHECK(has(2.52, 0.0, 0.8));   // the wall
  CHECK(!has(1.0, 0.0, 0.8));   // the room
  if (octomapAvailable()) CHECK(cells.size() == map.stats().octomap.occupiedLeaves);
  NavMapConfig noTree;
  noTree.octomapResolutionM = 0.0;  // no map.bt: no cloud either
  NavMap none(noTree, scene.voxel, scene.mu);
  none.setFrame(*map.frame());
  none.write(sb::test::scratchDir("navmap_surface_none"), &volume);
  CHECK(none.surfaceCells().empty());
}

TEST_CASE("a coarse volume raises map.bt's leaf to its voxel instead of failing the run", "[navmap]") {
  // 64^3 over 7.5 m (0.117 m voxels) with the default 0.1 m leaf: a run with odometry makes the map by itself,
  // and used to stop here ("octomap_resolution_m out of range").
  const NavMapConfig defaults;
  const double voxel = 7.5 / 64;
  REQUIRE_THROWS(defaults.validate(voxel));
  const NavMapConfig fitted = defaults.forVoxel(voxel);
  CHECK(fitted.octomapResolutionM == Approx(voxel));
  CHECK_NOTHROW(fitted.validate(voxel));
  CHECK_NOTHROW(NavMap(defaults, voxel, 0.1));
  CHECK(defaults.forVoxel(0.02).octomapResolutionM == Approx(0.1));  // a fine volume keeps the setting
  NavMapConfig none;
  none.octomapResolutionM = 0.0;
  CHECK(none.forVoxel(voxel).octomapResolutionM == 0.0);  // no map.bt stays none
}
