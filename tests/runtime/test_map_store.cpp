// The map kept across runs (runtime/map_store.h, runtime/map_store_format.h): the files round-trip; a
// truncated, altered or foreign-version file and a store made with another voxel size are refused naming the
// file, and nothing of a refused store is overwritten; a slab that left the moving volume comes back into it
// when the volume returns (swap-in) and raycasts as before it left (the skipping grid follows the written box);
// a second store opened on the first one's directory places its surface back for a candidate pose; a run never
// localised writes nothing into a kept store.

#include <catch2/catch.hpp>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "pipeline/cpu/cpu_backend.h"
#include "runtime/map_store.h"
#include "tests/pipeline/synthetic_room.h"
#include "tests/support/test_data.h"
#include "tests/support/store_files.h"

namespace fs = std::filesystem;
using sb::mapstore::SlabBox;

using sb::test::bytesOf;
using sb::test::writeBytes;
using sb::test::refusal;

namespace {

Eigen::Isometry3d at(double x, double y, double z) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, y, z);
  return pose;
}

// A 64^3 moving volume of 4 m (voxels of 1/16 m), as tests/runtime/test_map_slabs.cpp's.
sb::PipelineConfig smallConfig() {
  sb::PipelineConfig c;
  c.volumeResolution = 64;
  c.volumeSize = 4.0f;
  c.volumeShiftThreshold = 1.0f;
  c.volumeViewDistance = 1.2f;
  c.volumeMode = sb::VolumeMode::moving;
  return c;
}

std::vector<int16_t> wholeVolume(sb::CpuBackend& backend, int r) {
  std::vector<int16_t> v(2 * size_t(r) * size_t(r) * size_t(r));
  backend.readVolumeBox({0, 0, 0}, {r, r, r}, v.data());
  return v;
}

std::vector<float> raycastFrom(sb::CpuBackend& backend, const Eigen::Isometry3d& pose) {
  sb::StageTimes times;
  backend.raycast(pose.cast<float>(), 1, times);
  return backend.referenceVertices();
}

sb::Keyframe keyframeAt(const Eigen::Isometry3d& pose, uint8_t fill) {
  sb::Keyframe k;
  k.code.codes.assign(500, fill);
  k.code.codes[7] = uint8_t(fill + 3);
  k.T_camera_to_world = pose;
  k.frame = 42;
  return k;
}

// The store fed by the window: the slabs that leave the volume, and the boxes a shift brings back (swap-in). The
// three outlive the window's listeners.
void connect(sb::VolumeWindow& window, sb::MapStore& store, sb::CpuBackend& backend) {
  window.setSlabListener(
      [s = &store](sb::VolumeSlab&& slab) { s->addSlab(std::make_shared<const sb::VolumeSlab>(std::move(slab))); });
  window.setEnterListener(
      [s = &store, w = &window, b = &backend](const std::array<int, 3>& first, const std::array<int, 3>& extent) {
        s->swapIn(first, extent, *w, *b);
      });
}

// The room seen from four poses around (1.5, 1.5, 0.9), fused into the volume at corner 0.
void mapRoom(sb::CpuBackend& backend, const sb::Intrinsics& k) {
  for (int i = 0; i < 4; ++i) {
    const Eigen::Isometry3d pose = at(1.5 + i / 32.0, 1.5, 0.9 + i / 64.0);
    const sb::DepthFrame frame = sb::test::renderRoom(sb::test::Room{}, pose, k);
    sb::StageTimes times;
    backend.preprocess(frame.depth, float(1.0 / sb::test::kRoomDepthScale), 1, times);
    backend.integrate(pose.cast<float>(), times);
  }
}

// Away by 24 voxels along x (1.5 m: the slab x 0..23 leaves the volume at corner 0), then back by 24.
void awayAndBack(sb::VolumeWindow& window, sb::CpuBackend& backend) {
  REQUIRE(window.follow(at(3.5, 2.0, 0.8), backend) == Eigen::Vector3i(24, 0, 0));
  REQUIRE(window.follow(at(2.0, 2.0, 0.8), backend) == Eigen::Vector3i(-24, 0, 0));
}

struct Observed {
  size_t observed = 0;  // voxels observed in `before`
  size_t same = 0;      // of those, the ones `now` holds as they were
};
Observed sameObserved(const std::vector<int16_t>& before, const std::vector<int16_t>& now) {
  Observed o;
  for (size_t i = 0; i < before.size(); i += 2) {
    if (before[i + 1] == 0) continue;
    ++o.observed;
    o.same += before[i] == now[i] && before[i + 1] == now[i + 1];
  }
  return o;
}

}  // namespace

TEST_CASE("map store slab files round-trip and refuse truncated, altered or foreign-version bytes",
          "[map_store]") {
  const std::string dir = sb::test::scratchDir("map_store_format");
  fs::remove_all(dir);
  fs::create_directories(dir);
  SlabBox box;
  box.first = {-8, 3, 100};
  box.extent = {5, 4, 3};
  std::vector<int16_t> voxels(2 * box.voxels());
  for (size_t i = 0; i < box.voxels(); ++i) {
    const bool observed = i % 3 == 0 || i == box.voxels() - 1;
    voxels[2 * i] = observed ? int16_t(-1000 + int(i) * 37) : int16_t(32767);
    voxels[2 * i + 1] = observed ? int16_t(1 + i % 50) : int16_t(0);
  }
  const std::vector<uint8_t> bytes = sb::mapstore::encodeSlab(box, voxels.data());
  const std::string path = dir + "/slab-000000.tsdf";
  writeBytes(path, std::vector<char>(bytes.begin(), bytes.end()));
  const SlabBox read = sb::mapstore::readSlabHeader(path);
  CHECK(read.first == box.first);
  CHECK(read.extent == box.extent);
  // Merged into a larger box shifted by one voxel on x: observed voxels land, the others stay as they were.
  SlabBox target = box;
  target.first[0] -= 1;
  target.extent[0] += 2;
  std::vector<int16_t> out(2 * target.voxels(), int16_t(7));
  sb::mapstore::mergeSlab(path, target, out.data());
  for (int z = 0; z < box.extent[2]; ++z)
    for (int y = 0; y < box.extent[1]; ++y)
      for (int x = 0; x < box.extent[0]; ++x) {
        const size_t i = size_t(x) + size_t(box.extent[0]) * (size_t(y) + size_t(box.extent[1]) * size_t(z));
        const size_t j = size_t(x + 1) + size_t(target.extent[0]) * (size_t(y) + size_t(target.extent[1]) * size_t(z));
        if (voxels[2 * i + 1] != 0) {
          CHECK(out[2 * j] == voxels[2 * i]);
          CHECK(out[2 * j + 1] == voxels[2 * i + 1]);
        } else {
          CHECK(out[2 * j] == 7);
          CHECK(out[2 * j + 1] == 7);
        }
      }
  // Into a box that cuts the slab on every axis (and reaches past it on z): only the voxels inside land.
  SlabBox cut;
  cut.first = {box.first[0] + 2, box.first[1] + 1, box.first[2] + 1};
  cut.extent = {2, 2, 4};
  std::vector<int16_t> cutOut(2 * cut.voxels(), int16_t(7));
  sb::mapstore::mergeSlab(path, cut, cutOut.data());
  size_t landed = 0;
  for (int z = 0; z < cut.extent[2]; ++z)
    for (int y = 0; y < cut.extent[1]; ++y)
      for (int x = 0; x < cut.extent[0]; ++x) {
        const size_t j = size_t(x) + size_t(cut.extent[0]) * (size_t(y) + size_t(cut.extent[1]) * size_t(z));
        const int bx = x + 2, by = y + 1, bz = z + 1;
        const bool inBox = bz < box.extent[2];
        const size_t i = size_t(bx) + size_t(box.extent[0]) * (size_t(by) + size_t(box.extent[1]) * size_t(bz));
        INFO("cut voxel " << x << " " << y << " " << z);
        if (inBox && voxels[2 * i + 1] != 0) {
          CHECK(cutOut[2 * j] == voxels[2 * i]);
          CHECK(cutOut[2 * j + 1] == voxels[2 * i + 1]);
          ++landed;
        } else {
          CHECK(cutOut[2 * j] == 7);
          CHECK(cutOut[2 * j + 1] == 7);
        }
      }
  CHECK(landed > 0);
  // The payload's layout, as files already written hold it: per run skip and count (u32), then each voxel's
  // TSDF and weight (i16), little-endian. Voxel 0 is observed alone (-1000, weight 1).
  REQUIRE(bytes.size() > 64);
  const std::vector<uint8_t> firstRun{0, 0, 0, 0, 1, 0, 0, 0, 0x18, 0xfc, 1, 0};
  CHECK(std::vector<uint8_t>(bytes.begin() + 52, bytes.begin() + 64) == firstRun);

  // A box with nothing observed is not worth a file.
  std::vector<int16_t> empty(2 * box.voxels(), 0);
  CHECK(sb::mapstore::encodeSlab(box, empty.data()).empty());

  const std::vector<char> good(bytes.begin(), bytes.end());
  std::vector<char> truncated(good.begin(), good.end() - 5);
  writeBytes(path, truncated);
  std::string why = refusal([&] { sb::mapstore::readSlabHeader(path); });
  CHECK(why.find(path) != std::string::npos);
  CHECK(why.find("truncated") != std::string::npos);
  std::vector<char> altered = good;
  altered[good.size() - 3] ^= 0x10;
  writeBytes(path, altered);
  why = refusal([&] { sb::mapstore::readSlabHeader(path); });
  CHECK(why.find(path) != std::string::npos);
  CHECK(why.find("corrupt") != std::string::npos);
  std::vector<char> foreign = good;
  foreign[8] = 2;  // the format version's low byte
  writeBytes(path, foreign);
  why = refusal([&] { sb::mapstore::readSlabHeader(path); });
  CHECK(why.find(path) != std::string::npos);
  CHECK(why.find("format version 2") != std::string::npos);
}

TEST_CASE("map store keyframes round-trip and refuse a truncated file", "[map_store]") {
  const std::string dir = sb::test::scratchDir("map_store_keyframes");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const sb::Keyframe a = keyframeAt(at(1.0, -2.0, 3.5), 1), b = keyframeAt(at(-4.0, 0.25, 9.0), 9);
  const std::vector<uint8_t> bytes = sb::mapstore::encodeKeyframes({&a, &b});
  const std::string path = dir + "/keyframes.bin";
  writeBytes(path, std::vector<char>(bytes.begin(), bytes.end()));
  const std::vector<sb::Keyframe> read = sb::mapstore::readKeyframes(path);
  REQUIRE(read.size() == 2);
  CHECK(read[1].code.codes == b.code.codes);
  CHECK(read[1].T_camera_to_world.isApprox(b.T_camera_to_world, 0.0));
  CHECK(read[0].frame == 42);
  writeBytes(path, std::vector<char>(bytes.begin(), bytes.end() - 100));
  const std::string why = refusal([&] { sb::mapstore::readKeyframes(path); });
  CHECK(why.find(path) != std::string::npos);
  CHECK(why.find("truncated") != std::string::npos);
}

TEST_CASE("a slab that left comes back when the volume returns, and a kept store places its surface again",
          "[map_store]") {
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  const sb::PipelineConfig config = smallConfig();
  const int r = config.volumeResolution;
  sb::ThreadPool pool(2);
  const std::string dir = sb::test::scratchDir("map_store_swap");
  fs::remove_all(dir);
  const Eigen::Isometry3d seen = at(2.0, 2.0, 0.8);  // its view centre is the volume's centre at corner 0
  std::vector<int16_t> before;
  std::vector<float> raycastBefore;
  {
    sb::CpuBackend backend(config, k, pool);
    sb::VolumeWindow window(config);
    sb::MapStore store(dir, config);
    REQUIRE(!store.kept());
    REQUIRE(store.writing());
    connect(window, store, backend);
    mapRoom(backend, k);
    before = wholeVolume(backend, r);
    raycastBefore = raycastFrom(backend, seen);
    awayAndBack(window, backend);
    REQUIRE(window.cornerVoxels() == Eigen::Vector3i::Zero());
    const Observed after = sameObserved(before, wholeVolume(backend, r));
    REQUIRE(after.observed > 1000);
    CHECK(after.same == after.observed);
    CHECK(raycastFrom(backend, seen) == raycastBefore);  // the skipping grid knows the surface is back
    CHECK(store.summaryJson()["swap_ins"].get<size_t>() == 2);
    sb::KeyframeDatabase keyframes(10, 0.1);
    REQUIRE(keyframes.insert(keyframeAt(seen, 1)));
    store.finish(window, backend, keyframes);  // the final volume and the keyframe
    CHECK(store.summaryJson()["slab_files"].get<size_t>() == 2);
  }
  // A second run on the store: kept, placed for a far candidate and back, holds the surface again.
  std::map<std::string, std::vector<char>> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files[e.path().string()] = bytesOf(e.path().string());
  {
    sb::CpuBackend backend(config, k, pool);
    sb::VolumeWindow window(config);
    sb::MapStore store(dir, config);
    REQUIRE(store.kept());
    CHECK(!store.writing());
    REQUIRE(store.keptKeyframes().size() == 1);
    CHECK(store.keptKeyframes()[0].T_camera_to_world.isApprox(seen, 0.0));
    CHECK(store.placeFor(at(20.0, 1.5, 0.9), window, backend));
    CHECK(window.cornerVoxels() != Eigen::Vector3i::Zero());
    CHECK(!store.placeFor(seen, window, backend));  // one new placement per frame
    store.nextFrame();
    CHECK(store.placeFor(seen, window, backend));
    CHECK(store.placeFor(seen, window, backend));  // placed already: nothing to do
    REQUIRE(window.cornerVoxels() == Eigen::Vector3i::Zero());
    const Observed placed = sameObserved(before, wholeVolume(backend, r));
    CHECK(placed.same == placed.observed);
    CHECK(raycastFrom(backend, seen) == raycastBefore);
    CHECK(store.summaryJson()["placements"].get<size_t>() == 2);
    // Never localised: its end writes nothing into the kept store.
    sb::KeyframeDatabase keyframes(10, 0.1);
    store.finish(window, backend, keyframes);
  }
  for (const auto& [path, bytes] : files) CHECK(bytesOf(path) == bytes);
  size_t count = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir)) count += e.is_regular_file();
  CHECK(count == files.size());
}

TEST_CASE("a store of another format version or voxel size, or a folder of other files, is refused untouched",
          "[map_store]") {
  const sb::PipelineConfig config = smallConfig();
  const std::string dir = sb::test::scratchDir("map_store_refused");
  fs::remove_all(dir);
  { sb::MapStore store(dir, config); }
  const std::string format = dir + "/format.json";
  const std::vector<char> original = bytesOf(format);
  REQUIRE(!original.empty());
  sb::PipelineConfig other = config;
  other.volumeResolution = 128;  // voxels of 1/32 m
  std::string why = refusal([&] { sb::MapStore store(dir, other); });
  CHECK(why.find(format) != std::string::npos);
  CHECK(why.find("voxel_size_m") != std::string::npos);
  CHECK(bytesOf(format) == original);

  std::string text(original.begin(), original.end());
  text.replace(text.find("\"version\": 1"), 12, "\"version\": 7");
  writeBytes(format, std::vector<char>(text.begin(), text.end()));
  why = refusal([&] { sb::MapStore store(dir, config); });
  CHECK(why.find(format) != std::string::npos);
  CHECK(why.find("format version 7") != std::string::npos);
  CHECK(bytesOf(format) == std::vector<char>(text.begin(), text.end()));

  const std::string folder = sb::test::scratchDir("map_store_not_a_store");
  fs::remove_all(folder);
  fs::create_directories(folder);
  std::ofstream(folder + "/notes.txt") << "mine\n";
  why = refusal([&] { sb::MapStore store(folder, config); });
  CHECK(why.find("no format.json") != std::string::npos);
  CHECK(!fs::exists(folder + "/format.json"));

  sb::PipelineConfig fixed = config;
  fixed.volumeMode = sb::VolumeMode::fixed;
  CHECK(refusal([&] { sb::MapStore store(dir + "-fixed", fixed); }).find("moving volume") != std::string::npos);
}

TEST_CASE("an ordinary run's slabs kept in memory: the volume kept, placed far and back, the oldest dropped past "
          "the bound",
          "[map_store]") {
  // The in-run relocalisation's store (MapStore::inMemory; docs/moving-volume.md "Relocalising over the whole
  // run"): no directory, no file; the volume kept whole before a placement comes back when placed again.
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  const sb::PipelineConfig config = smallConfig();
  const int r = config.volumeResolution;
  sb::ThreadPool pool(2);
  sb::CpuBackend backend(config, k, pool);
  sb::VolumeWindow window(config);
  const std::unique_ptr<sb::MapStore> store = sb::MapStore::inMemory(config, uint64_t(64) << 20);
  REQUIRE(store->inMemory());
  REQUIRE(store->writing());
  REQUIRE(!store->kept());
  connect(window, *store, backend);
  const Eigen::Isometry3d seen = at(2.0, 2.0, 0.8);
  mapRoom(backend, k);
  const std::vector<int16_t> before = wholeVolume(backend, r);
  const std::vector<float> raycastBefore = raycastFrom(backend, seen);
  const auto allBack = [&](const std::vector<int16_t>& now) {
    const Observed o = sameObserved(before, now);
    REQUIRE(o.observed > 1000);
    return o.same == o.observed;
  };
  // A slab leaves and comes back: kept, but not swapped in before a relocalisation placed the volume (the run
  // maps as one that keeps nothing).
  awayAndBack(window, backend);
  CHECK_FALSE(allBack(wholeVolume(backend, r)));
  CHECK(store->summaryJson()["swap_ins"].get<size_t>() == 0);
  // Lost: the volume holds the newest map where it stands (nothing kept yet); kept whole by the first placement,
  // for a far candidate (nothing of it there), and placed back.
  store->recoveryStarted(window);
  CHECK(store->placeFor(seen, window, backend));  // no placement needed: the volume stays, nothing kept
  CHECK(store->summaryJson()["placements"].get<size_t>() == 0);
  CHECK(store->summaryJson()["volumes_kept"].get<size_t>() == 0);
  CHECK(store->placeFor(at(20.0, 1.5, 0.9), window, backend));
  CHECK(window.cornerVoxels() != Eigen::Vector3i::Zero());
  const std::vector<int16_t> far = wholeVolume(backend, r);
  size_t left = 0;
  for (size_t i = 1; i < far.size(); i += 2) left += far[i] != 0;
  CHECK(left == 0);
  CHECK(!store->placeFor(seen, window, backend));  // one new placement per frame
  store->nextFrame();
  CHECK(store->placeFor(seen, window, backend));
  REQUIRE(window.cornerVoxels() == Eigen::Vector3i::Zero());
  CHECK(allBack(wholeVolume(backend, r)));  // the slab that left and the volume kept, merged
  CHECK(raycastFrom(backend, seen) == raycastBefore);
  // Relocalised: from now on a slab that leaves comes back when the volume returns (swap-in).
  awayAndBack(window, backend);
  CHECK(allBack(wholeVolume(backend, r)));
  CHECK(store->summaryJson()["swap_ins"].get<size_t>() == 2);
  const nlohmann::json summary = store->summaryJson();
  INFO(summary.dump());
  CHECK(summary["in_memory"] == true);
  CHECK(summary["volumes_kept"].get<size_t>() == 1);
  CHECK(summary["placements"].get<size_t>() == 2);
  CHECK(summary["slabs"].get<size_t>() == 3);  // the slab that left, the whole volume, the slab that left again
  CHECK(summary["slabs_dropped"].get<size_t>() == 0);

  // Bounded below one slab's bytes: each new slab drops the oldest (the newest always stays).
  const std::unique_ptr<sb::MapStore> small = sb::MapStore::inMemory(config, 1);
  small->keepVolume(window, backend);
  small->keepVolume(window, backend);
  small->nextFrame();
  CHECK(small->placeFor(at(20.0, 1.5, 0.9), window, backend));  // drains the worker
  const nlohmann::json bounded = small->summaryJson();
  INFO(bounded.dump());
  CHECK(bounded["slabs"].get<size_t>() == 1);
  CHECK(bounded["slabs_dropped"].get<size_t>() == 1);
  CHECK(refusal([&] { sb::MapStore::inMemory(config, 0); }).find("bound") != std::string::npos);
}
