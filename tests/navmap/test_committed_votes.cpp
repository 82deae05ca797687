// The slabs' votes on the worker thread (navmap/committed_votes.h): a grid or a map written right after a
// slab is handed over holds it, byte for byte as when the SLAM thread voted; the slabs' copies are let go
// once voted; a full queue makes the producer wait, never drops a slab; a map destroyed with slabs queued
// stops. Also built with ThreadSanitizer (test_committed_votes_tsan).
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <sstream>

#include "navmap/nav_map.h"
#include "navmap/nav_map_sink.h"
#include "tests/navmap/tsdf_scene.h"
#include "tests/support/test_data.h"

using namespace sb;
using namespace sb::navmap;
using sb::navmap::test::TsdfScene;

namespace {

constexpr int kRes = 120;    // a 2.4 m cube of 2 cm voxels
constexpr int kPlanes = 12;  // per slab: 10 slabs along z
constexpr double kVoxel = 0.02;

MapFrame levelFrame() {
  Eigen::Isometry3d camera = Eigen::Isometry3d::Identity();
  camera.translation() = Eigen::Vector3d(1.2, 1.0, 0.1);
  return mapFrameFromMount(camera, CameraMount{1.2, 0.0, 0.0});
}

// A floor (world y = 2.2), a wall along z at x = 2 and a box in the band: surface in every slab.
const TsdfScene& scene() {
  static const TsdfScene s(
      [](const Eigen::Vector3d& w) {
        const Eigen::Vector3d q =
            (w - Eigen::Vector3d(0.8, 1.8, 1.2)).cwiseAbs() - Eigen::Vector3d(0.2, 0.3, 0.5);
        const double box = q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
        return std::min({2.2 - w.y(), 2.0 - w.x(), box});
      },
      kRes, kVoxel);
  return s;
}

// Planes z0 .. z0 + kPlanes - 1 of the scene, as a copy (what the moving volume hands over).
std::shared_ptr<const std::vector<int16_t>> slabCopy(int z0) {
  const size_t plane = 2 * size_t(kRes) * kRes;
  const auto& v = scene().voxels;
  return std::make_shared<const std::vector<int16_t>>(v.begin() + ptrdiff_t(plane * size_t(z0)),
                                                      v.begin() + ptrdiff_t(plane * size_t(z0 + kPlanes)));
}

VoxelBox slabBoxOf(const std::vector<int16_t>& voxels, int z0) {
  VoxelBox b;
  b.data = voxels.data();
  b.dims = b.extent = {kRes, kRes, kPlanes};
  b.corner = Eigen::Vector3d(0, 0, z0 * kVoxel);
  b.voxelSizeM = kVoxel;
  return b;
}

std::string fileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

TEST_CASE("slabs voted on the worker: a map written right after holds every slab handed over", "[navmap]") {
  const double mu = scene().mu;
  // Before: the SLAM thread votes each slab itself (addCommitted).
  NavMap reference(NavMapConfig{}, kVoxel, mu);
  reference.setFrame(levelFrame());
  for (int z0 = 0; z0 < kRes; z0 += kPlanes) {
    const auto copy = slabCopy(z0);
    REQUIRE(reference.addCommitted(slabBoxOf(*copy, z0)));
  }
  const std::filesystem::path before = sb::test::scratchDir("committed_votes_before"),
                              after = sb::test::scratchDir("committed_votes_after");
  const OccupancyImage expected = reference.write(before.string(), nullptr);
  REQUIRE(expected.count(CellState::occupied) > 0);

  // After: handed to the worker (the only reference to each copy goes with it), written at once.
  NavMap map(NavMapConfig{}, kVoxel, mu);
  map.setFrame(levelFrame());
  std::vector<std::weak_ptr<const std::vector<int16_t>>> copies;
  for (int z0 = 0; z0 < kRes; z0 += kPlanes) {
    auto copy = slabCopy(z0);
    copies.push_back(copy);
    const VoxelBox box = slabBoxOf(*copy, z0);
    const size_t bytes = copy->size() * sizeof(int16_t);
    REQUIRE(map.queueCommitted(box, std::move(copy), bytes));
  }
  const OccupancyImage written = map.write(after.string(), nullptr);
  CHECK(written.cells == expected.cells);
  CHECK(written.originM.isApprox(expected.originM));
  for (const char* name : {"map.pgm", "map.yaml", "map.bt"}) {
    INFO(name);
    CHECK(std::filesystem::exists(before / name) == std::filesystem::exists(after / name));
    CHECK(fileBytes(after / name) == fileBytes(before / name));
  }
  CHECK(map.surfaceCells() == reference.surfaceCells());
  CHECK(map.stats().slabs == size_t(kRes / kPlanes));
  CHECK(map.stats().volumeCells == reference.stats().volumeCells);
  for (const auto& copy : copies) CHECK(copy.expired());  // every copy let go once voted

  // The grid (the daemon's ?MAP) right after one more slab holds it too.
  NavMap partial(NavMapConfig{}, kVoxel, mu);
  partial.setFrame(levelFrame());
  auto first = slabCopy(0);
  const VoxelBox box = slabBoxOf(*first, 0);
  REQUIRE(partial.queueCommitted(box, std::move(first), 0));
  CHECK(partial.grid().count(CellState::occupied) > 0);
}

TEST_CASE("slabs voted on the worker: a full queue makes the producer wait, no slab is dropped", "[navmap]") {
  CommittedVotes votes(NavMapConfig{}.forVoxel(kVoxel), scene().mu, /*queueBytes=*/1);
  GridVotes expected;
  const Eigen::Isometry3d T = levelFrame().T_world_to_map;
  for (int round = 0; round < 3; ++round)
    for (int z0 = 0; z0 < kRes; z0 += kPlanes) {
      auto copy = slabCopy(z0);
      VoxelBox box = slabBoxOf(*copy, z0);
      box.muM = scene().mu;
      voteGrid(box, T, NavMapConfig{}.forVoxel(kVoxel), expected);
      votes.queue(box, T, copy, copy->size() * sizeof(int16_t));  // over the bound: one at a time
    }
  votes.drain();
  const CommittedStats s = votes.stats();
  CHECK(s.boxes == size_t(3 * kRes / kPlanes));
  CHECK(s.waitMs <= s.queueMs);
  const NavMapConfig config = NavMapConfig{}.forVoxel(kVoxel);
  CHECK(gridImage(votes.grid(), config, kVoxel).cells == gridImage(expected, config, kVoxel).cells);
}

TEST_CASE("slabs voted on the worker: a map destroyed with slabs queued stops and lets them go", "[navmap]") {
  std::vector<std::weak_ptr<const std::vector<int16_t>>> copies;
  {
    NavMap map(NavMapConfig{}, kVoxel, scene().mu);
    map.setFrame(levelFrame());
    for (int round = 0; round < 4; ++round)
      for (int z0 = 0; z0 < kRes; z0 += kPlanes) {
        auto copy = slabCopy(z0);
        copies.push_back(copy);
        const VoxelBox box = slabBoxOf(*copy, z0);
        REQUIRE(map.queueCommitted(box, std::move(copy), 0));
      }
  }
  for (const auto& copy : copies) CHECK(copy.expired());
}

TEST_CASE("slabs before the map frame is known are not queued", "[navmap]") {
  NavMap map(NavMapConfig{}, kVoxel, scene().mu);
  auto copy = slabCopy(0);
  const VoxelBox box = slabBoxOf(*copy, 0);
  CHECK_FALSE(map.queueCommitted(box, copy, 0));
  CHECK(copy.use_count() == 1);
  CHECK(map.stats().slabs == 0);
}

TEST_CASE("the run's sink hands each slab's shared copy to the worker; its grid holds them all", "[navmap]") {
  PipelineConfig pipeline;
  pipeline.volumeResolution = kRes;
  pipeline.volumeSize = float(kRes * kVoxel);
  const double voxel = double(pipeline.volumeSize) / pipeline.volumeResolution;
  NavMapSink sink(NavMapConfig{}, pipeline, Intrinsics{}, 1000.0);
  Eigen::Isometry3d camera = Eigen::Isometry3d::Identity(), toOdom = Eigen::Isometry3d::Identity();
  camera.translation() = Eigen::Vector3d(1.2, 1.0, 0.1);
  toOdom.linear() =
      Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();  // camera y down
  toOdom.translation() = Eigen::Vector3d(0, 0, 1.2);
  sink.setFrameFromOdometry(camera, toOdom);
  REQUIRE(sink.map().frame());
  NavMap reference(NavMapConfig{}, voxel, double(pipeline.mu));
  reference.setFrame(*sink.map().frame());
  std::vector<std::weak_ptr<const VolumeSlab>> copies;
  size_t shift = 0;
  for (int z0 = 0; z0 < kRes; z0 += kPlanes) {
    auto slab = std::make_shared<VolumeSlab>();
    slab->voxels = *slabCopy(z0);
    slab->resolution = kRes;
    slab->first = {0, 0, z0};
    slab->extent = {kRes, kRes, kPlanes};
    slab->corner = Eigen::Vector3d(0, 0, z0 * kVoxel);
    slab->voxelSize = float(kVoxel);
    slab->axis = 2;
    slab->shift = ++shift;
    REQUIRE(reference.addCommitted(slabBox(*slab)));
    copies.push_back(slab);
    sink.onSlab(std::move(slab));  // the sink's is the only reference left
  }
  const OccupancyImage grid = sink.grid(), expected = reference.grid();
  REQUIRE(expected.count(CellState::occupied) > 0);
  CHECK(grid.cells == expected.cells);
  CHECK(sink.map().stats().slabs == shift);
  for (const auto& copy : copies) CHECK(copy.expired());
  CHECK(sink.summaryJson()["slabs"] == shift);
}
