#pragma once
// The scene the test camera driver (test_camera_driver.cpp) renders, shared with the tests that re-render it
// to compare: the inside of a box room seen by a pinhole camera that looks along +z (y down) and slides along
// +x by kStepMetres per device frame. Depth in millimetres (or 100 um units), 0 where nothing is hit.

#include <cmath>
#include <cstdint>

namespace sb::test {

constexpr double kHorizontalFovRad = 1.0122909661567112;  // 58 degrees, a PrimeSense-like field of view
constexpr double kVerticalFovRad = 0.7853981633974483;    // 45 degrees
constexpr double kStepMetres = 0.003;                      // camera motion along +x per device frame
// Room walls (metres, camera start at the origin): asymmetric, so a mirrored image differs.
constexpr double kLeft = -1.2, kRight = 2.0, kCeiling = -1.2, kFloor = 1.0, kBack = 3.0;

inline double roomFx(int width) { return 0.5 * width / std::tan(0.5 * kHorizontalFovRad); }
inline double roomFy(int height) { return 0.5 * height / std::tan(0.5 * kVerticalFovRad); }

// Depth (metres along the optical axis) seen at pixel (u, v) of a width x height image (principal point at
// the image centre, OpenNI2's convention) with the camera at x = cameraX.
inline double roomDepthMetres(int u, int v, int width, int height, double cameraX) {
  const double a = (u - 0.5 * width) / roomFx(width);
  const double b = (v - 0.5 * height) / roomFy(height);
  double z = kBack;
  if (a > 0) z = std::fmin(z, (kRight - cameraX) / a);
  if (a < 0) z = std::fmin(z, (kLeft - cameraX) / a);
  if (b > 0) z = std::fmin(z, kFloor / b);
  if (b < 0) z = std::fmin(z, kCeiling / b);
  return z;
}

// Raw depth value in `unitsPerMetre` (1000: millimetres, 10000: 100 um).
inline uint16_t roomDepthRaw(int u, int v, int width, int height, double cameraX, double unitsPerMetre) {
  return static_cast<uint16_t>(std::lround(roomDepthMetres(u, v, width, height, cameraX) * unitsPerMetre));
}

}  // namespace sb::test
