// The band's classification on TSDF volumes filled from a distance function (tsdf_scene.h), and the hand-over
// of a slab that leaves the moving volume.
#include <catch2/catch.hpp>
#include <cmath>

#include "navmap/nav_map.h"
#include "navmap/nav_map_sink.h"
#include "tests/navmap/tsdf_scene.h"

using namespace sb;
using namespace sb::navmap;
using sb::navmap::test::TsdfScene;

namespace {

// The first camera at world (2, 1, 0.5), level, 1.2 m above the floor (world y = 2.2): map x = world z - 0.5,
// map y = 2 - world x, map z = 2.2 - world y.
MapFrame levelFrame() {
  Eigen::Isometry3d camera = Eigen::Isometry3d::Identity();
  camera.translation() = Eigen::Vector3d(2.0, 1.0, 0.5);
  return mapFrameFromMount(camera, CameraMount{1.2, 0.0, 0.0});
}

double floorSdf(const Eigen::Vector3d& w) { return 2.2 - w.y(); }

double boxSdf(const Eigen::Vector3d& p, const Eigen::Vector3d& centre, const Eigen::Vector3d& half) {
  const Eigen::Vector3d q = (p - centre).cwiseAbs() - half;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

OccupancyImage gridOf(const TsdfScene& scene) {
  NavMap map(NavMapConfig{}, scene.voxel, scene.mu);
  map.setFrame(levelFrame());
  map.refreshLive(scene.box());
  return map.grid();
}

CellState at(const OccupancyImage& g, double mx, double my) {
  const int x = int(std::floor((mx - g.originM.x()) / g.resolutionM));
  const int y = int(std::floor((my - g.originM.y()) / g.resolutionM));
  if (x < 0 || y < 0 || x >= g.width || y >= g.height) return CellState::unknown;  // no vote: outside
  return CellState(g.at(x, y));
}

}  // namespace

TEST_CASE("band: a floor is free, never occupied", "[navmap]") {
  const OccupancyImage g = gridOf(TsdfScene(floorSdf));
  CHECK(g.count(CellState::occupied) == 0);
  CHECK(at(g, 1.0, 0.0) == CellState::free);
  CHECK(at(g, 3.0, 1.5) == CellState::free);
}

TEST_CASE("band: a wall is occupied where it stands, unknown behind it", "[navmap]") {
  // A wall facing the camera at world z = 3 (map x = 2.5), solid behind.
  const OccupancyImage g = gridOf(TsdfScene([](const Eigen::Vector3d& w) { return std::min(floorSdf(w), 3.0 - w.z()); }));
  CHECK(at(g, 2.52, 0.0) == CellState::occupied);
  CHECK(at(g, 2.52, -1.2) == CellState::occupied);
  CHECK(at(g, 2.0, 0.0) == CellState::free);
  CHECK(at(g, 2.42, 0.0) == CellState::free);  // the cell in front of it
  CHECK(at(g, 2.62, 0.0) == CellState::unknown);  // inside the wall: no vote
  // Only the wall's cells are occupied: one column of cells along it.
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x)
      if (g.at(x, y) == int8_t(CellState::occupied)) CHECK(std::abs(g.originM.x() + (x + 0.5) * g.resolutionM - 2.525) < 0.03);
}

TEST_CASE("band: a table top above the band is not an obstacle", "[navmap]") {
  // A 1 m x 1 m top from 1.6 to 1.7 m above the floor (map x 1-2, y -0.5-0.5), no legs.
  const Eigen::Vector3d centre(2.0, 2.2 - 1.65, 2.0), half(0.5, 0.05, 0.5);
  const OccupancyImage g =
      gridOf(TsdfScene([&](const Eigen::Vector3d& w) { return std::min(floorSdf(w), boxSdf(w, centre, half)); }));
  CHECK(g.count(CellState::occupied) == 0);
  CHECK(at(g, 1.5, 0.0) == CellState::free);
  // The same top at 1.0-1.1 m is in the band: occupied under it.
  const Eigen::Vector3d low(2.0, 2.2 - 1.05, 2.0);
  const OccupancyImage h =
      gridOf(TsdfScene([&](const Eigen::Vector3d& w) { return std::min(floorSdf(w), boxSdf(w, low, half)); }));
  CHECK(at(h, 1.5, 0.0) == CellState::occupied);
}

TEST_CASE("band: a ramp is free below the band and occupied where it rises into it", "[navmap]") {
  // The floor rises at 0.25 m/m from map x = 1 (world z = 1.5): 0.1 m up at map x = 1.4.
  const double slope = 0.25, c = 1.0 / std::sqrt(1.0 + slope * slope);
  const OccupancyImage g = gridOf(TsdfScene([&](const Eigen::Vector3d& w) {
    const double mx = w.z() - 0.5, mz = 2.2 - w.y();
    return (mz - slope * std::max(0.0, mx - 1.0)) * (mx > 1.0 ? c : 1.0);
  }));
  CHECK(at(g, 0.5, 0.0) == CellState::free);
  CHECK(at(g, 1.22, 0.0) == CellState::free);  // 0.06 m up: under the band
  CHECK(at(g, 1.82, 0.0) == CellState::occupied);  // 0.21 m up
  CHECK(at(g, 3.02, 0.5) == CellState::occupied);  // 0.5 m up
}

TEST_CASE("slab hand-over: a cell on the slab's boundary is counted once", "[navmap]") {
  // A side wall at world x = 3 (map y = -1) runs across the boundary; the floor under everything.
  const TsdfScene scene([](const Eigen::Vector3d& w) { return std::min(floorSdf(w), 3.0 - w.x()); });
  const OccupancyImage whole = gridOf(scene);
  const int R = scene.resolution, k = 77;  // the boundary at world z = 1.54 m: map x 1.04, inside cell [1.00, 1.05)
  for (const bool towardsPlus : {true, false}) {
    DYNAMIC_SECTION("shift towards " << (towardsPlus ? "+z" : "-z")) {
      // The slab: planes that leave plus the first that stays (pipeline/volume_window.cpp).
      VolumeSlab slab;
      slab.resolution = R;
      slab.axis = 2;
      slab.voxelSize = float(scene.voxel);
      const int first = towardsPlus ? 0 : k, thickness = towardsPlus ? k + 1 : R - k;
      slab.first = {0, 0, first};
      slab.extent = {R, R, thickness};
      slab.corner = Eigen::Vector3d(0, 0, first * scene.voxel);
      const size_t plane = 2 * size_t(R) * size_t(R);
      slab.voxels.assign(scene.voxels.begin() + ptrdiff_t(plane * size_t(first)),
                         scene.voxels.begin() + ptrdiff_t(plane * size_t(first + thickness)));
      // What stays: towards +z planes k .. R-1, towards -z planes 0 .. k.
      VoxelBox stays = scene.box();
      stays.first[2] = towardsPlus ? k : 0;
      stays.extent[2] = towardsPlus ? R - k : k + 1;
      NavMap map(NavMapConfig{}, scene.voxel, scene.mu);
      map.setFrame(levelFrame());
      REQUIRE(map.addCommitted(slabBox(slab)));
      map.refreshLive(stays);
      const OccupancyImage split = map.grid();
      CHECK(at(split, 1.02, -1.02) == CellState::occupied);
      CHECK(at(whole, 1.02, -1.02) == CellState::occupied);
      CHECK(at(split, 1.02, 0.0) == CellState::free);
      REQUIRE(split.width == whole.width);
      REQUIRE(split.height == whole.height);
      CHECK(split.originM.isApprox(whole.originM));
      CHECK(split.cells == whole.cells);
    }
  }
}
