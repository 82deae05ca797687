// The map's worker thread and its retention (runtime/map_slabs.h): the slabs that leave a 64^3 volume over
// three shifts (forward along x, a jump of a whole side back, then down in y: copies across the cyclic
// buffer's wrap) are handed to MapSlabs as copies and written by its worker:
// - byte for byte the files that meshing each slab in place on the SLAM thread (the volume read through the
//   offset before the shift, as before the worker) and writing it gives, whatever the queue's bound (one slab
//   at a time: back-pressure, never a drop);
// - the destructor writes what is still queued; a write that fails is thrown at the next drain, naming it;
// - retention: past keepBytes the oldest files go (the newest stays), mesh.ply holds the kept ones; files of
// an
//   earlier start count first and this run's number on after them.

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "mesh/ply_writer.h"
#include "pipeline/cpu/cpu_backend.h"
#include "runtime/map_slabs.h"
#include "tests/pipeline/synthetic_room.h"
#include "tests/support/test_data.h"

namespace {

namespace fs = std::filesystem;

Eigen::Isometry3d at(double x, double y, double z) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, y, z);
  return pose;
}

std::string bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// The slabs of a drive through the room, as the window hands them over, and for each the bytes of its mesh
// made the way the SLAM thread made it before the worker: in place through the offset (empty: no surface).
struct Drive {
  std::vector<sb::VolumeSlab> slabs;
  std::vector<std::string> reference;
};

const Drive& drive() {
  static const Drive d = [] {
    Drive out;
    const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
    sb::PipelineConfig config;
    config.volumeResolution = 64;
    config.volumeSize = 4.0f;
    config.volumeShiftThreshold = 1.0f;
    config.volumeViewDistance = 1.2f;
    sb::ThreadPool pool(2);
    sb::CpuBackend backend(config, k, pool);
    sb::VolumeWindow window(config);
    const std::string scratch = sb::test::scratchDir("map_slabs_worker_reference") + "/slab.ply";
    window.setSlabListener([&](sb::VolumeSlab&& slab) {
      sb::VolumeView view{backend.volumeData(), slab.resolution, 4.0f};
      view.offset = window.offset();
      view.first = slab.first;
      view.extent = slab.extent;
      sb::Mesh mesh = sb::extractMesh(view);
      std::string bytes;
      if (!mesh.triangles.empty()) {
        sb::transformMesh(mesh, Eigen::Isometry3f(Eigen::Translation3f(slab.corner.cast<float>())));
        sb::writePly(scratch, mesh);
        bytes = bytesOf(scratch);
      }
      out.reference.push_back(bytes);
      out.slabs.push_back(std::move(slab));
    });
    const auto fuse = [&](const Eigen::Isometry3d& pose) {
      const sb::DepthFrame frame = sb::test::renderRoom(sb::test::Room{}, pose, k);
      sb::StageTimes times;
      backend.preprocess(frame.depth, float(1.0 / sb::test::kRoomDepthScale), 1, times);
      backend.integrate(pose.cast<float>(), times);
    };
    for (int i = 0; i < 3; ++i) fuse(at(1.5 + i / 32.0, 1.5, 0.9 + i / 64.0));
    REQUIRE(window.follow(at(3.5, 2.0, 0.8), backend) == Eigen::Vector3i(24, 0, 0));
    for (int i = 0; i < 2; ++i) fuse(at(2.0 + i / 32.0, 1.5, 1.0));
    // A jump of a whole side back along x: the whole volume leaves (corner -2.5 m, offset 24).
    REQUIRE(window.follow(at(-0.5, 2.0, 0.8), backend) == Eigen::Vector3i(-64, 0, 0));
    for (int i = 0; i < 2; ++i) fuse(at(1.4 + i / 32.0, 1.5, 0.9));
    // Down: the ceiling's planes leave, read across the wrap in x.
    REQUIRE(window.follow(at(0.2, 3.2, 0.8), backend) == Eigen::Vector3i(0, 16, 0));
    return out;
  }();
  return d;
}

std::string freshDir(const std::string& name) {
  const std::string dir = sb::test::scratchDir(name);
  fs::remove_all(dir);
  return dir;
}

}  // namespace

TEST_CASE("map slabs: the worker writes the files the SLAM thread wrote, byte for byte", "[map_slabs]") {
  const Drive& d = drive();
  REQUIRE(d.slabs.size() == 3);
  size_t withSurface = 0;
  for (const std::string& r : d.reference) withSurface += !r.empty();
  for (size_t i = 0; i < d.reference.size(); ++i)
    UNSCOPED_INFO("slab " << i + 1 << ": " << d.reference[i].size() << " bytes");
  REQUIRE(withSurface >= 3);
  // The default bound, and one slab at a time (every add after the first waits for the worker).
  const bool oneAtATime = GENERATE(false, true);
  const size_t bound = oneAtATime ? size_t(1) : sb::MapSlabs::kDefaultQueueBytes;
  INFO("queue bound " << bound << " bytes");
  const std::string dir = freshDir("map_slabs_worker");
  sb::MapSlabs slabs(dir, sb::MapSlabs::Options{bound, 0});
  for (const sb::VolumeSlab& slab : d.slabs) slabs.add(slab);
  const std::vector<std::string> files = slabs.files();  // drains
  REQUIRE(files.size() == withSurface);
  size_t file = 0;
  for (size_t i = 0; i < d.slabs.size(); ++i) {
    const std::string path = dir + "/map_slabs/slab-" + std::string(6 - std::to_string(i + 1).size(), '0') +
                             std::to_string(i + 1) + ".ply";
    INFO("slab " << i + 1);
    CHECK(fs::exists(path) == !d.reference[i].empty());
    if (d.reference[i].empty()) continue;
    CHECK(files[file++] == path);
    CHECK(bytesOf(path) == d.reference[i]);
  }
  const sb::MapSlabsStats stats = slabs.stats();
  size_t largest = 0;
  for (const sb::VolumeSlab& slab : d.slabs) largest = std::max(largest, slab.bytes());
  CHECK(stats.peakQueuedBytes <= std::max(bound, largest));
  if (oneAtATime) CHECK(stats.peakQueuedBytes == largest);  // never two slabs at once
  CHECK(stats.workerMs > 0.0);
  CHECK(fs::directory_iterator(dir + "/map_slabs") != fs::directory_iterator());
  for (const auto& entry : fs::directory_iterator(dir + "/map_slabs"))
    CHECK(entry.path().extension() == ".ply");  // no .partial left
}

TEST_CASE("map slabs: the destructor writes what is queued; a failed write is thrown, naming it",
          "[map_slabs]") {
  const Drive& d = drive();
  const std::string dir = freshDir("map_slabs_worker_end");
  {
    sb::MapSlabs slabs(dir);
    for (const sb::VolumeSlab& slab : d.slabs) slabs.add(slab);
  }  // no drain: the destructor finishes the queue
  size_t expected = 0;
  for (const std::string& r : d.reference) expected += !r.empty();
  CHECK(size_t(std::distance(fs::directory_iterator(dir + "/map_slabs"), fs::directory_iterator())) ==
        expected);

  const std::string blocked = freshDir("map_slabs_worker_blocked");
  fs::create_directories(fs::path(blocked).parent_path());
  std::ofstream(blocked) << "a file where the run directory should be";
  sb::MapSlabs failing(blocked);
  failing.add(d.slabs[0]);
  CHECK_THROWS_WITH(failing.drain(), Catch::Contains("cannot create") && Catch::Contains(blocked));
  CHECK_NOTHROW(failing.drain());  // thrown once
  fs::remove(blocked);
}

TEST_CASE("map slabs: retention keeps the newest files within the bound, earlier starts' first to go",
          "[map_slabs]") {
  const Drive& d = drive();
  const std::string dir = freshDir("map_slabs_retention");
  // An earlier start left two slabs (numbers 1 and 7).
  fs::create_directories(dir + "/map_slabs");
  std::ofstream(dir + "/map_slabs/slab-000001.ply") << std::string(1000, 'x');
  std::ofstream(dir + "/map_slabs/slab-000007.ply") << std::string(1000, 'y');
  std::vector<uint64_t> sizes;
  for (const std::string& r : d.reference)
    if (!r.empty()) sizes.push_back(r.size());
  REQUIRE(sizes.size() >= 3);
  // Room for the last two slabs of this run, not three.
  const uint64_t keep = sizes[sizes.size() - 1] + sizes[sizes.size() - 2] + 1;
  REQUIRE(keep < sizes[sizes.size() - 1] + sizes[sizes.size() - 2] + sizes[sizes.size() - 3]);
  sb::MapSlabs slabs(dir, sb::MapSlabs::Options{sb::MapSlabs::kDefaultQueueBytes, keep});
  for (const sb::VolumeSlab& slab : d.slabs) slabs.add(slab);
  const std::vector<std::string> files = slabs.files();
  REQUIRE(files.size() == 2);
  std::vector<std::string> left;
  for (const auto& entry : fs::directory_iterator(dir + "/map_slabs"))
    left.push_back(entry.path().filename());
  std::sort(left.begin(), left.end());
  CHECK(left == std::vector<std::string>{fs::path(files[0]).filename(), fs::path(files[1]).filename()});
  // Numbered on after the earlier start's 7: this run's shift n is file 7 + n.
  size_t lastShift = 0;
  for (size_t i = 0; i < d.reference.size(); ++i)
    if (!d.reference[i].empty()) lastShift = i + 1;
  CHECK(fs::path(files[1]).filename() == "slab-0000" + std::to_string(7 + lastShift) + ".ply");
  CHECK(slabs.stats().removedFiles == 2 + sizes.size() - 2);
  // The map holds the kept slabs and the final volume.
  sb::Mesh last;
  last.vertices = {Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(1, 0, 0), Eigen::Vector3f(0, 1, 0)};
  last.normals.assign(3, Eigen::Vector3f(0, 0, 1));
  last.triangles = {{0, 1, 2}};
  CHECK(slabs.writeMap(dir + "/mesh.ply", last) > 1);

  // With no limit nothing goes.
  const std::string all = freshDir("map_slabs_no_retention");
  sb::MapSlabs unbounded(all);
  for (const sb::VolumeSlab& slab : d.slabs) unbounded.add(slab);
  CHECK(unbounded.files().size() == sizes.size());
  CHECK(unbounded.stats().removedFiles == 0);
}
