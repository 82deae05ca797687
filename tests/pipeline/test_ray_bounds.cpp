// The ray bounds (pipeline/ray_bounds.h) against their definition, by brute force: no ray of a tile meets a
// block of distance 0 before the tile's tMin, nor after its tMax (the bit-identity of the raycast with and
// without them is test_ray_bounds_identity.cpp's). Here with a block beside the camera, outside the view and
// across its plane, which once made every tile's bound 0.

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <vector>

#include "kernels/raycast.h"
#include "pipeline/ray_bounds.h"

namespace {

constexpr int kRes = 64;       // voxels per side
constexpr float kSize = 3.2f;  // metres: 5 cm voxels
constexpr int kShift = SB_SKIP_SHIFT;
constexpr int kBlocks = kRes >> kShift;

// The block of distance 0 holding the point p (metres, volume frame).
void mark(std::vector<uint8_t>& distance, float x, float y, float z) {
  const float voxel = kSize / kRes;
  const int b[3] = {int(x / voxel) >> kShift, int(y / voxel) >> kShift, int(z / voxel) >> kShift};
  distance[size_t(b[0]) + size_t(kBlocks) * (size_t(b[1]) + size_t(kBlocks) * size_t(b[2]))] = 0;
}

}  // namespace

TEST_CASE("ray bounds: no ray meets a surface block outside its tile's bounds", "[pipeline][raycast]") {
  const int width = GENERATE(80, 320), height = width * 3 / 4;  // groups of blocks, then single blocks
  const float f = 0.9f * float(width);
  const SbCamera k{f, f, 0.5f * float(width - 1), 0.5f * float(height - 1)};
  std::vector<uint8_t> distance(size_t(kBlocks) * kBlocks * kBlocks, 1);
  // A wall 1 m in front of the camera (at z = 1.0 m, looking along +z from the volume's centre) with a hole,
  // a few blocks in front of it, and one block beside the camera, outside the view and across its plane.
  const float cx = 1.6f, cy = 1.6f, cz = 1.0f;
  for (float x = 0.6f; x < 2.6f; x += 0.05f)
    for (float y = 0.6f; y < 2.6f; y += 0.05f)
      if (std::fabs(x - 1.8f) > 0.2f || std::fabs(y - 1.5f) > 0.2f) mark(distance, x, y, cz + 1.0f);
  mark(distance, 1.3f, 1.4f, cz + 0.6f);
  mark(distance, 1.9f, 1.8f, cz + 0.8f);
  mark(distance, cx - 0.6f, cy, cz - 0.05f);  // beside the camera, its box across the camera plane
  const SbMat34 pose = {{1, 0, 0, cx, 0, 1, 0, cy, 0, 0, 1, cz}};
  sb::RayBounds bounds;
  bounds.compute(distance.data(), kShift, kRes, kSize, pose, k, width, height);
  REQUIRE((width * height >= sb::RayBounds::kFinePixels) == (width == 320));
  // Every pixel's ray, sampled every 1/8 voxel: the samples whose interpolation cell's lower corner lies in a
  // block of distance 0 (what the march would sample there) are within the tile's [tMin, tMax].
  const float voxel = kSize / kRes, dt = voxel / 8.0f;
  int bitten = 0, tested = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const int tile = (y / sb::RayBounds::kTile) * bounds.columns() + x / sb::RayBounds::kTile;
      const float tMin = bounds.bounds()[2 * size_t(tile)], tMax = bounds.bounds()[2 * size_t(tile) + 1];
      const float u = (float(x) - k.cx) / k.fx, v = (float(y) - k.cy) / k.fy;
      for (float t = 0.0f; t < 4.0f; t += dt) {
        const float s[3] = {(cx + u * t) / voxel - 0.5f, (cy + v * t) / voxel - 0.5f,
                            (cz + t) / voxel - 0.5f};
        if (s[0] < 0 || s[1] < 0 || s[2] < 0 || s[0] >= kRes - 1 || s[1] >= kRes - 1 || s[2] >= kRes - 1)
          continue;
        const int b[3] = {int(s[0]) >> kShift, int(s[1]) >> kShift, int(s[2]) >> kShift};
        if (distance[size_t(b[0]) + size_t(kBlocks) * (size_t(b[1]) + size_t(kBlocks) * size_t(b[2]))] != 0)
          continue;
        ++tested;
        if (t < tMin || t > tMax) {
          INFO("pixel " << x << ", " << y << " at t " << t << " outside [" << tMin << ", " << tMax << "]");
          FAIL("a surface block outside its tile's bounds");
        }
      }
      bitten += tMin > 0.5f;
    }
  // The block beside the camera bounds nothing: most tiles start past half a metre (the nearest block in view
  // lies 0.6 m ahead), or this proves nothing.
  CHECK(bitten > width * height / 2);
  CHECK(tested > width * height);  // samples in surface blocks, at least one per ray on average
}
