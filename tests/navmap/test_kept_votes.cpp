// The navigation map kept in a map store (navmap/kept_votes.h; issue 55): the frame and the votes round-trip byte
// for byte; a map that continues from a kept one and votes the rest of a scene gives the grid and the 3D cells of
// one map that voted all of it, in the kept frame; a payload cut short, with a frame that is not rigid, with runs
// that do not cover a chunk or cast with other settings is refused naming the file (and the setting).
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>

#include "core/error.h"
#include "navmap/kept_votes.h"
#include "navmap/nav_map.h"
#include "tests/navmap/tsdf_scene.h"
#include "tests/support/store_files.h"

using namespace sb::navmap;

using sb::test::refusal;

namespace {

// A corridor along world z: walls at x = 1 and x = 3, the floor at y = 2.6 (map z = 0), 4 cm voxels.
sb::navmap::test::TsdfScene corridor() {
  return sb::navmap::test::TsdfScene(
      [](const Eigen::Vector3d& w) { return std::min({w.x() - 1.0, 3.0 - w.x(), 2.6 - w.y()}); }, 100, 0.04);
}

std::unique_ptr<NavMap> mapOf(const sb::navmap::test::TsdfScene& scene, bool framed = true) {
  auto map = std::make_unique<NavMap>(NavMapConfig{}, scene.voxel, scene.mu);
  Eigen::Isometry3d camera = Eigen::Isometry3d::Identity();
  camera.translation() = Eigen::Vector3d(2.0, 1.4, 0.3);
  if (framed) map->setFrame(mapFrameFromMount(camera, CameraMount{1.2, 5.0, 0.0}));
  return map;
}

// The scene's voxels with z in [from, to): a slab that left the volume.
VoxelBox part(const sb::navmap::test::TsdfScene& scene, int from, int to) {
  VoxelBox b = scene.box();
  b.first = {0, 0, from};
  b.extent = {scene.resolution, scene.resolution, to - from};
  return b;
}

}  // namespace

TEST_CASE("a map continued from its kept votes is the map of both parts, in the kept frame", "[navmap][map_store]") {
  const auto scene = corridor();
  const auto whole = mapOf(scene);
  whole->addCommitted(part(scene, 0, 50));
  whole->addCommitted(part(scene, 50, 100));

  const auto first = mapOf(scene);  // run 1: the first half left its volume
  first->addCommitted(part(scene, 0, 50));
  const std::vector<uint8_t> payload = encodeKeptVotes(first->kept(nullptr), first->config());
  const KeptVotes back = decodeKeptVotes(payload, "S/navmap.bin", first->config());
  CHECK(encodeKeptVotes(back, first->config()) == payload);  // byte for byte
  CHECK(back.frame.T_world_to_map.isApprox(first->frame()->T_world_to_map));
  CHECK(back.frame.source == first->frame()->source);

  const auto second = mapOf(scene, /*framed=*/false);  // run 2: no frame of its own, the kept one's
  second->restore(back);
  REQUIRE(second->frame());
  second->addCommitted(part(scene, 50, 100));
  const OccupancyImage a = whole->grid(), b = second->grid(), onlyFirst = first->grid();
  CHECK(b.width == a.width);
  CHECK(b.height == a.height);
  CHECK(b.originM.isApprox(a.originM));
  CHECK(b.cells == a.cells);
  CHECK(a.count(CellState::occupied) > 0);
  CHECK(a.count(CellState::free) > onlyFirst.count(CellState::free));  // the second half adds to the map
  CHECK(encodeKeptVotes(second->kept(nullptr), second->config()) ==
        encodeKeptVotes(whole->kept(nullptr), whole->config()));  // map.bt's 3D cells too

  // The end of a run keeps the volume's votes with the committed ones.
  const VoxelBox volume = part(scene, 50, 100);
  CHECK(encodeKeptVotes(first->kept(&volume), first->config()) ==
        encodeKeptVotes(whole->kept(nullptr), whole->config()));
}

TEST_CASE("kept votes cut short, not rigid, not covering a chunk or cast with other settings are refused",
          "[navmap][map_store]") {
  const auto scene = corridor();
  const auto map = mapOf(scene);
  map->addCommitted(part(scene, 0, 100));
  const KeptVotes kept = map->kept(nullptr);
  const std::vector<uint8_t> payload = encodeKeptVotes(kept, map->config());

  std::vector<uint8_t> cut(payload.begin(), payload.end() - 5);
  CHECK(refusal([&] { decodeKeptVotes(cut, "S/navmap.bin", map->config()); }).find("'S/navmap.bin'") !=
        std::string::npos);
  cut.assign(payload.begin(), payload.begin() + 40);
  CHECK(refusal([&] { decodeKeptVotes(cut, "S/navmap.bin", map->config()); }).find("truncated") != std::string::npos);

  std::vector<uint8_t> longer = payload;
  longer.push_back(0);
  CHECK(refusal([&] { decodeKeptVotes(longer, "S/navmap.bin", map->config()); }).find("bytes after its 3D cells") !=
        std::string::npos);

  KeptVotes skewed;
  skewed.frame = kept.frame;
  skewed.frame.T_world_to_map.linear()(0, 0) = 3.0;
  CHECK(refusal([&] { decodeKeptVotes(encodeKeptVotes(skewed, map->config()), "S/navmap.bin", map->config()); })
            .find("not a rigid transform") != std::string::npos);

  // The first chunk's first run made empty (0 skipped, 0 cells): no run may be.
  KeptVotes one;
  one.frame = kept.frame;
  one.grid.add(3, 4, 1, 0);
  std::vector<uint8_t> bad = encodeKeptVotes(one, map->config());
  const size_t runAt = 96 + 4 + one.frame.source.size() + 40 + 4 + 8;
  REQUIRE(bad[runAt] + 256 * bad[runAt + 1] == 4 * 64 + 3);  // cell (3, 4): 4 rows of 64 and 3 skipped
  bad[runAt] = bad[runAt + 1] = bad[runAt + 2] = bad[runAt + 3] = 0;
  CHECK(refusal([&] { decodeKeptVotes(bad, "S/navmap.bin", map->config()); }).find("do not cover a chunk") !=
        std::string::npos);

  NavMapConfig coarser = map->config();
  coarser.resolutionM = 0.1;
  const std::string why = refusal([&] { decodeKeptVotes(payload, "S/navmap.bin", coarser); });
  CHECK(why.find("'S/navmap.bin'") != std::string::npos);
  CHECK(why.find("resolution_m 0.05") != std::string::npos);
  NavMapConfig lower = map->config();
  lower.bandMaxM = 1.0;
  CHECK(refusal([&] { decodeKeptVotes(payload, "S/navmap.bin", lower); }).find("band_max_m") != std::string::npos);
}
