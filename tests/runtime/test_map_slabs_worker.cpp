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

#include <array>
#include <sys/mount.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "core/segment_store.h"
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
  sb::MapSlabs slabs(dir, sb::MapSlabs::Options{bound, 0, nullptr});
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
  sb::MapSlabs slabs(dir, sb::MapSlabs::Options{sb::MapSlabs::kDefaultQueueBytes, keep, nullptr});
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

TEST_CASE(
    "map slabs: under the store's free-space floor the oldest slabs go, the newest stays, the run goes on",
    "[map_slabs]") {
  const Drive& d = drive();
  const std::string dir = freshDir("map_slabs_floor");
  fs::create_directories(dir);
  sb::RetentionLimits limits;
  limits.minFreeBytes = 1ull << 50;  // no file system has a petabyte free: always below the floor
  auto store = std::make_shared<sb::SegmentStore>(dir, limits);
  // A closed segment older than every slab: it goes first.
  std::ofstream(dir + "/frames-000001.jsonl") << "{}\n";
  store->addClosed(dir + "/frames-000001.jsonl", 3, 0);
  sb::MapSlabs::Options options;
  options.store = store;
  sb::MapSlabs slabs(dir, options);
  for (const sb::VolumeSlab& slab : d.slabs) slabs.add(slab);
  const std::vector<std::string> files = slabs.files();  // drains: no failure
  REQUIRE(files.size() == 1);
  CHECK(files[0] == dir + "/map_slabs/slab-000003.ply");
  CHECK(bytesOf(files[0]) == d.reference[2]);
  CHECK_FALSE(fs::exists(dir + "/map_slabs/slab-000001.ply"));
  CHECK_FALSE(fs::exists(dir + "/map_slabs/slab-000002.ply"));
  CHECK_FALSE(fs::exists(dir + "/frames-000001.jsonl"));
  CHECK(slabs.stats().removedForSpace == 2);
  CHECK(slabs.stats().removedFiles == 2);
  CHECK(store->usage().removedAttached == 2);
  CHECK(store->usage().removedSegments == 1);
  const sb::MapSlabFiles onDisk = sb::mapSlabFiles(dir);
  CHECK(onDisk.files == 1);
  CHECK(onDisk.bytes == d.reference[2].size());
}

TEST_CASE("map slabs: a slab that finds the disk full removes the oldest slab and is written",
          "[map_slabs]") {
  // A real full disk (a tmpfs; root only): a slab's temporaries are new files of their own names
  // (core/exclusive_file.h), so no fixed name can be linked to /dev/full any more (issue 44).
  if (::geteuid() != 0) {
    WARN("skipped: not root, no tmpfs to stand for a full disk");
    return;
  }
  const Drive& d = drive();
  REQUIRE(d.slabs.size() == 3);
  struct Unmount {
    std::string dir;
    ~Unmount() { ::umount2(dir.c_str(), MNT_DETACH); }
  };
  const auto freeBytes = [](const std::string& dir) {
    struct statvfs fs {};
    REQUIRE(::statvfs(dir.c_str(), &fs) == 0);
    return uint64_t(fs.f_bavail) * fs.f_frsize;
  };
  const auto fill = [&](const std::string& path, uint64_t leave) {  // leaves about `leave` bytes free
    std::FILE* f = std::fopen(path.c_str(), "wb");
    REQUIRE(f);
    const std::string block(4096, 'x');
    while (freeBytes(fs::path(path).parent_path().string()) > leave + block.size() &&
           std::fwrite(block.data(), 1, block.size(), f) == block.size() && std::fflush(f) == 0) {
    }
    std::fclose(f);
  };
  // With the daemon's store: before slab 3 the store makes room for twice the largest slab (M3), which
  // removes slab 1 (the oldest; the newest written, 2, stays), and slab 3 is written.
  const std::string dir = freshDir("map_slabs_disk_full");
  fs::create_directories(dir);
  REQUIRE(::mount("tmpfs", dir.c_str(), "tmpfs", 0, "size=64m") == 0);
  Unmount unmount{dir};
  sb::RetentionLimits limits;
  limits.minFreeBytes = 0;
  sb::MapSlabs::Options options;
  options.store = std::make_shared<sb::SegmentStore>(dir, limits);
  sb::MapSlabs slabs(dir, options);
  slabs.add(d.slabs[0]);
  slabs.add(d.slabs[1]);
  slabs.drain();
  const uint64_t size1 = d.reference[0].size(), size3 = d.reference[2].size();
  const uint64_t need = 2 * size3 + (64 << 10);  // slab 3 at its peak, and a margin
  fill(dir + "/filler", need > size1 ? need - size1 : 0);
  slabs.add(d.slabs[2]);
  const std::vector<std::string> files = slabs.files();
  CHECK(files ==
        std::vector<std::string>{dir + "/map_slabs/slab-000002.ply", dir + "/map_slabs/slab-000003.ply"});
  CHECK(bytesOf(dir + "/map_slabs/slab-000003.ply") == d.reference[2]);
  CHECK(slabs.stats().removedForSpace == 1);
  CHECK(options.store->usage().removedAttached == 1);

  // Without a store (slambooster run: every slab kept) the full disk fails, naming the file and the reason.
  const std::string plain = freshDir("map_slabs_disk_full_plain");
  fs::create_directories(plain);
  REQUIRE(::mount("tmpfs", plain.c_str(), "tmpfs", 0, "size=64m") == 0);
  Unmount unmountPlain{plain};
  sb::MapSlabs failing(plain);
  failing.add(d.slabs[0]);
  failing.add(d.slabs[1]);
  failing.drain();
  fill(plain + "/filler", 0);
  failing.add(d.slabs[2]);
  CHECK_THROWS_WITH(failing.drain(), Catch::Contains("slab-000003.ply") && Catch::Contains("No space left"));
}

namespace {

// A binary PLY as writePly writes it (x y z nx ny nz, triangles) back into a mesh.
sb::Mesh parsePly(const std::string& bytes) {
  const size_t end = bytes.find("end_header\n");
  REQUIRE(end != std::string::npos);
  const auto count = [&](const std::string& element) {
    const size_t at = bytes.find("element " + element + " ");
    REQUIRE(at < end);
    return size_t(std::stoull(bytes.substr(at + element.size() + 9)));
  };
  const size_t vertices = count("vertex"), faces = count("face");
  const char* p = bytes.data() + end + 11;
  REQUIRE(bytes.size() == end + 11 + vertices * 24 + faces * 13);
  sb::Mesh mesh;
  for (size_t i = 0; i < vertices; ++i, p += 24) {
    float f[6];
    std::memcpy(f, p, sizeof f);  // little-endian hosts (x86-64, armhf)
    mesh.vertices.emplace_back(f[0], f[1], f[2]);
    mesh.normals.emplace_back(f[3], f[4], f[5]);
  }
  for (size_t i = 0; i < faces; ++i, p += 13) {
    std::array<uint32_t, 3> t;
    std::memcpy(t.data(), p + 1, sizeof t);
    mesh.triangles.push_back(t);
  }
  return mesh;
}

// The bytes after the header (the merged file's header has its own comment).
std::string body(const std::string& bytes) {
  return bytes.substr(bytes.find("end_header\n") + 11);
}

}  // namespace

TEST_CASE("map slabs: mesh.ply is every slab file then the final volume, byte for byte, streamed in pieces",
          "[map_slabs]") {
  const Drive& d = drive();
  const std::string dir = freshDir("map_slabs_merge");
  sb::MapSlabs slabs(dir);
  for (const sb::VolumeSlab& slab : d.slabs) slabs.add(slab);
  // A final volume larger than the merge's pieces (16384 vertices or faces).
  sb::Mesh last;
  for (int i = 0; i < 40000; ++i) {
    last.vertices.emplace_back(0.001f * float(i), 0.5f, -0.25f * float(i % 7));
    last.normals.emplace_back(0.0f, float(i % 2), float((i + 1) % 2));
  }
  for (uint32_t i = 0; i + 2 < 40000; i += 2) last.triangles.push_back({i, i + 1, i + 2});
  const size_t triangles = slabs.writeMap(dir + "/mesh.ply", last);
  // The same mesh in one piece: the slabs' meshes (from the bytes of the reference) and `last`, indices moved
  // on.
  sb::Mesh all;
  for (const std::string& r : d.reference) {
    if (r.empty()) continue;
    const sb::Mesh part = parsePly(r);
    const uint32_t offset = uint32_t(all.vertices.size());
    all.vertices.insert(all.vertices.end(), part.vertices.begin(), part.vertices.end());
    all.normals.insert(all.normals.end(), part.normals.begin(), part.normals.end());
    for (const auto& t : part.triangles)
      all.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  }
  const uint32_t offset = uint32_t(all.vertices.size());
  all.vertices.insert(all.vertices.end(), last.vertices.begin(), last.vertices.end());
  all.normals.insert(all.normals.end(), last.normals.begin(), last.normals.end());
  for (const auto& t : last.triangles) all.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  CHECK(triangles == all.triangles.size());
  const std::string reference = dir + "/reference.ply";
  sb::writePly(reference, all);
  const std::string merged = bytesOf(dir + "/mesh.ply");
  CHECK(merged.find("element vertex " + std::to_string(all.vertices.size()) + "\n") != std::string::npos);
  CHECK(merged.find("element face " + std::to_string(all.triangles.size()) + "\n") != std::string::npos);
  CHECK(body(merged) == body(bytesOf(reference)));
}
