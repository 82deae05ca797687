// The CPU backend's raycast (pipeline/cpu/cpu_raycast.h) against kernels/raycast.h's sbRaycastPixel: bit-identical
// vertex and normal maps (memcmp) on integrated room volumes (camera inside the volume, outside it looking
// in and looking away, surfaces cut by the volume's faces, grazing rays along the floor, rays with direction
// components exactly 0) and on a noise volume, at the sizes of csr 1, 2, 4 and 8, with skipping grids of 4^3
// and 8^3 voxel blocks and without skipping (at the two large sizes the backend's 4^3 blocks only); and
// CpuBackend::raycast bit-identical for 1, 2 and 3 threads and to the kernel without skipping.

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "kernels/raycast.h"
#include "pipeline/block_distance.h"
#include "pipeline/cpu/cpu_backend.h"
#include "pipeline/cpu/cpu_raycast.h"
#include "pipeline/kernel_args.h"
#include "tests/pipeline/synthetic_room.h"

using sb::test::kRoomDepthScale;

namespace {

struct Maps {
  std::vector<float> vertex, normal;
  Maps(int w, int h) : vertex(3 * size_t(w) * h), normal(3 * size_t(w) * h) {}
};

// The skipping grid of block_distance.h from the masks of kernels/raycast.h's sbBlockSurfaceMask.
std::vector<uint8_t> distanceGrid(const int16_t* volume, int resolution, int shift, float below) {
  const int n = resolution >> shift;
  std::vector<uint8_t> masks(size_t(n) * n * n, 0), distance;
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        masks[x + (y + size_t(z) * n) * n] =
            sbBlockSurfaceMask(volume, resolution, SbVoxelOffset{}, shift, sb::surfaceTsdfBelow(below), x, y, z);
  sb::ThreadPool pool(1);
  sb::computeBlockDistance(masks, n, distance, pool);
  return distance;
}

sb::RaycastInputs inputs(const sb::PipelineConfig& c, const int16_t* volume, const uint8_t* distance, int shift,
                         const Eigen::Isometry3d& pose, const sb::Intrinsics& k) {
  sb::RaycastInputs in;
  in.volume = volume;
  in.resolution = c.volumeResolution;
  in.size = c.volumeSize;
  in.blockDistance = distance;
  in.distanceShift = shift;
  in.cameraToWorld = sb::toMat34(pose.cast<float>().matrix());
  in.camera = sb::toCamera(k);
  in.nearPlane = c.nearPlane;
  in.farPlane = c.farPlane;
  in.largeStep = c.raycastLargeStep * c.mu;
  in.smallStep = c.raycastSmallStep * c.voxelSize();
  in.smallStepBelow = c.raycastSmallStepBelow;
  return in;
}

Maps kernelMaps(const sb::RaycastInputs& in, int w, int h) {
  Maps m(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      sbRaycastPixel(m.vertex.data(), m.normal.data(), w, in.volume, in.resolution, in.offset, in.size, in.blockDistance,
                     in.distanceShift, in.cameraToWorld, in.camera, in.nearPlane, in.farPlane,
                     in.largeStep, in.smallStep, in.smallStepBelow, -1e30f, 1e30f, x, y);
  return m;
}

// In 8 x 8 tiles as the backend calls it (the last row and column of tiles cut short).
Maps cpuMaps(const sb::RaycastInputs& in, int w, int h) {
  Maps m(w, h);
  for (int y = 0; y < h; y += 8)
    for (int x = 0; x < w; x += 8)
      sb::raycastRect(in, m.vertex.data(), m.normal.data(), w, x, std::min(w, x + 8), y, std::min(h, y + 8));
  return m;
}

struct Comparison {
  size_t pixels = 0, hits = 0, differing = 0, firstDifference = 0;
};

Comparison compare(const Maps& a, const Maps& b) {
  Comparison c;
  c.pixels = a.normal.size() / 3;
  for (size_t i = 0; i < c.pixels; ++i) {
    if (a.normal[3 * i] != SB_INVALID_NORMAL) ++c.hits;
    if (std::memcmp(&a.vertex[3 * i], &b.vertex[3 * i], 3 * sizeof(float)) != 0 ||
        std::memcmp(&a.normal[3 * i], &b.normal[3 * i], 3 * sizeof(float)) != 0) {
      if (c.differing++ == 0) c.firstDifference = i;
    }
  }
  return c;
}

Eigen::Isometry3d pose(const Eigen::Vector3d& position, double yawDegrees, double pitchDegrees = 0.0) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() = position;
  p.linear() = (Eigen::AngleAxisd(yawDegrees * M_PI / 180.0, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(pitchDegrees * M_PI / 180.0, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return p;
}

struct View {
  const char* what;
  Eigen::Isometry3d pose;
  unsigned scenesWithHits;  // bit s: more than 2% of the rays hit a surface in scene s
  bool noHits;              // no ray hits a surface
};

}  // namespace

TEST_CASE("raycastRect's maps are bit-identical to sbRaycastPixel's", "[pipeline][raycast]") {
  // 0: the room inside a 3 m volume; 1: the room cut by the faces of a 2 m volume (the right wall at 2.2 m and
  // the back wall at 2.7 m lie outside it); 2: a 1 m volume of noise (mostly positive: rays march a while).
  const int scene = GENERATE(0, 1, 2);
  sb::PipelineConfig config;
  config.volumeSize = scene == 0 ? 3.0f : (scene == 1 ? 2.0f : 1.0f);
  config.volumeResolution = scene == 0 ? 128 : (scene == 1 ? 64 : 32);
  const sb::Intrinsics full = sb::test::roomIntrinsics(640, 480);
  sb::ThreadPool pool(2);
  sb::CpuBackend backend(config, sb::test::roomIntrinsics(160, 120), pool);
  std::vector<int16_t> noise;
  const int16_t* volume = backend.volumeData();
  if (scene < 2) {
    const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
    sb::StageTimes times;
    for (const Eigen::Isometry3d& view : {pose({1.5, 1.5, 0.9}, 0), pose({1.5, 1.5, 0.9}, 0),
                                          pose({1.9, 1.6, 2.6}, -126), pose({1.2, 1.4, 1.0}, 30, -20)}) {
      backend.preprocess(sb::test::renderRoom(sb::test::Room{}, view, k).depth, float(1.0 / kRoomDepthScale), 1,
                         times);
      backend.integrate(view.cast<float>(), times);
    }
  } else {
    const int r = config.volumeResolution;
    noise.resize(2 * size_t(r) * r * r);
    uint32_t seed = 12345u;
    for (size_t i = 0; i < noise.size(); i += 2) {
      seed = seed * 1664525u + 1013904223u;
      const int v = int(seed >> 16) % 32768;
      noise[i] = static_cast<int16_t>((seed >> 8) % 16 == 0 ? -v : v);
      noise[i + 1] = static_cast<int16_t>(seed >> 24);
    }
    volume = noise.data();
  }
  const float size = config.volumeSize;
  // The room's positions; the noise volume is a third of the room's 3 m: positions scaled to it.
  const double at = scene == 2 ? size / 3.0 : 1.0;
  const std::vector<View> views = {
      {"inside, ahead", pose(at * Eigen::Vector3d(1.5, 1.5, 0.9), 0), 0b111, false},
      {"inside, moved and turned", pose(at * Eigen::Vector3d(1.65, 1.4, 1.1), 25, 10), 0b101, false},
      {"inside, grazing the floor", pose(at * Eigen::Vector3d(1.4, 1.95, 1.0), -10, 1), 0b111, false},
      // Unobserved space (+1) up to the volume's faces: every ray leaves the volume.
      {"inside, towards the volume's faces", pose(at * Eigen::Vector3d(1.2, 1.3, 1.3), 140, -30), 0, false},
      {"outside, looking in through z = 0", pose({0.4 * size, 0.47 * size, -0.6}, 5), 0b111, false},
      {"outside, looking in through x = size", pose({size + 0.7, 1.5 * at, 0.5 * size}, -100), 0b111, false},
      {"outside, looking away", pose({0.5 * size, 0.5 * size, -0.5}, 180), 0, true},
  };
  std::vector<uint8_t> grid4 = distanceGrid(volume, config.volumeResolution, 2, config.raycastSmallStepBelow);
  std::vector<uint8_t> grid8 = distanceGrid(volume, config.volumeResolution, 3, config.raycastSmallStepBelow);
  for (const int csr : {1, 2, 4, 8}) {
    sb::Intrinsics k = full.scaled(csr);
    for (size_t v = 0; v < views.size(); ++v) {
      if (csr == 1 && v >= 1) continue;  // the large image for one view only (time under qemu-arm)
      for (const int shift : {2, 3, -1}) {
        if (csr <= 2 && shift != 2) continue;  // the backend's grid only at the large sizes
        const uint8_t* distance = shift == 2 ? grid4.data() : (shift == 3 ? grid8.data() : nullptr);
        const sb::RaycastInputs in = inputs(config, volume, distance, shift < 0 ? 0 : shift, views[v].pose, k);
        const Comparison c = compare(kernelMaps(in, k.width, k.height), cpuMaps(in, k.width, k.height));
        INFO("scene " << scene << ", " << views[v].what << ", csr " << csr << " (" << k.width << "x" << k.height
                      << "), skipping blocks " << (shift < 0 ? 0 : 1 << shift) << ": " << c.differing << " of "
                      << c.pixels << " pixels differ (first " << c.firstDifference << "), " << c.hits << " hits");
        CHECK(c.differing == 0);
        if ((views[v].scenesWithHits >> scene) & 1) CHECK(c.hits > c.pixels / 50);
        if (views[v].noHits) CHECK(c.hits == 0);
      }
    }
  }
  // Rays with direction components exactly 0 (no inverse, no skipping along that axis): the principal point
  // on a pixel and the camera axis-aligned.
  sb::Intrinsics axis = full.scaled(4);
  axis.cx = 80.0f;
  axis.cy = 60.0f;
  const Eigen::Isometry3d aligned = pose({0.5 * size, 0.52 * size, 0.3 * size}, 0);
  for (const uint8_t* distance : {static_cast<const uint8_t*>(grid4.data()), static_cast<const uint8_t*>(nullptr)}) {
    const sb::RaycastInputs in = inputs(config, volume, distance, 2, aligned, axis);
    const Comparison c = compare(kernelMaps(in, axis.width, axis.height), cpuMaps(in, axis.width, axis.height));
    INFO("scene " << scene << ", axis-aligned rays: " << c.differing << " of " << c.pixels << " differ (first "
                  << c.firstDifference << ")");
    CHECK(c.differing == 0);
  }
}

TEST_CASE("CpuBackend::raycast is bit-identical for any thread count and to the kernel without skipping",
          "[pipeline][raycast]") {
  sb::PipelineConfig config;
  config.volumeSize = 3.0f;
  config.volumeResolution = 128;
  const sb::Intrinsics k = sb::test::roomIntrinsics(200, 150);
  const Eigen::Isometry3d start = pose({1.5, 1.5, 0.9}, 0), moved = pose({1.6, 1.45, 1.0}, 12, -5);
  std::vector<Maps> results;
  for (const unsigned threads : {1u, 2u, 3u}) {
    sb::ThreadPool pool(threads);
    sb::CpuBackend backend(config, k, pool);
    sb::StageTimes times;
    for (const Eigen::Isometry3d& view : {start, start, moved}) {
      backend.preprocess(sb::test::renderRoom(sb::test::Room{}, view, k).depth, float(1.0 / kRoomDepthScale), 1,
                         times);
      backend.integrate(view.cast<float>(), times);
    }
    backend.raycast(moved.cast<float>(), 1, times);
    Maps m(k.width, k.height);
    m.vertex = backend.referenceVertices();
    m.normal = backend.referenceNormals();
    // The backend skips with its own grid; skipping leaves the maps unchanged, so they equal the kernel's
    // without any.
    const Maps plain = kernelMaps(inputs(config, backend.volumeData(), nullptr, 0, moved, k), k.width, k.height);
    const Comparison c = compare(plain, m);
    INFO(threads << " threads: " << c.differing << " of " << c.pixels << " pixels differ from the kernel's");
    CHECK(c.differing == 0);
    CHECK(c.hits > c.pixels / 2);
    results.push_back(m);
  }
  for (size_t i = 1; i < results.size(); ++i) CHECK(compare(results[0], results[i]).differing == 0);
}

// raycastRect keeps several rays in flight, each taking the next pixel when its march ends (across rows and
// 8-pixel columns of a large rectangle); the samples of a moved volume read through the cyclic offset (a cell
// across the buffer's wrap takes the kernel).
TEST_CASE("raycastRect on a moved (cyclic) volume and over a whole image is bit-identical to sbRaycastPixel",
          "[pipeline][raycast]") {
  sb::PipelineConfig config;
  config.volumeSize = 3.0f;
  config.volumeResolution = 64;
  const int r = config.volumeResolution;
  sb::ThreadPool pool(1);
  sb::CpuBackend backend(config, sb::test::roomIntrinsics(160, 120), pool);
  const sb::Intrinsics room = sb::test::roomIntrinsics(160, 120);
  sb::StageTimes times;
  for (const Eigen::Isometry3d& view : {pose({1.5, 1.5, 0.9}, 0), pose({1.9, 1.6, 2.6}, -126)}) {
    backend.preprocess(sb::test::renderRoom(sb::test::Room{}, view, room).depth, float(1.0 / kRoomDepthScale), 1,
                       times);
    backend.integrate(view.cast<float>(), times);
  }
  const int16_t* logical = backend.volumeData();
  // The logical grid of blocks does not move with the buffer.
  const std::vector<uint8_t> grid = distanceGrid(logical, r, 2, config.raycastSmallStepBelow);
  const sb::Intrinsics k = sb::test::roomIntrinsics(640, 480).scaled(4);
  for (const SbVoxelOffset o : {SbVoxelOffset{0, 0, 0}, SbVoxelOffset{5, 17, 40}, SbVoxelOffset{63, 1, 32}}) {
    std::vector<int16_t> moved(2 * size_t(r) * r * r);
    for (int z = 0; z < r; ++z)
      for (int y = 0; y < r; ++y)
        for (int x = 0; x < r; ++x)
          for (int c = 0; c < 2; ++c)
            moved[2 * size_t(sbVoxelIndex(r, o, x, y, z)) + c] = logical[2 * (x + (y + size_t(z) * r) * r) + c];
    for (const Eigen::Isometry3d& view : {pose({1.5, 1.5, 0.9}, 0), pose({1.65, 1.4, 1.1}, 25, 10)}) {
      for (const uint8_t* distance : {static_cast<const uint8_t*>(grid.data()), static_cast<const uint8_t*>(nullptr)}) {
        sb::RaycastInputs in = inputs(config, moved.data(), distance, 2, view, k);
        in.offset = o;
        // The whole image as one rectangle (lanes move on across rows and tiles), and in 8 x 8 tiles.
        Maps whole(k.width, k.height);
        sb::raycastRect(in, whole.vertex.data(), whole.normal.data(), k.width, 0, k.width, 0, k.height);
        const Maps reference = kernelMaps(in, k.width, k.height);
        const Comparison a = compare(reference, whole), b = compare(reference, cpuMaps(in, k.width, k.height));
        INFO("offset " << o.x << " " << o.y << " " << o.z << (distance ? ", skipping" : ", no skipping") << ": "
                       << a.differing << " (whole) and " << b.differing << " (tiles) of " << a.pixels
                       << " differ, " << a.hits << " hits");
        CHECK(a.hits > a.pixels / 10);
        CHECK(a.differing == 0);
        CHECK(b.differing == 0);
      }
    }
  }
}
