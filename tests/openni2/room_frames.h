#pragma once
// Checks of frames from the test camera driver against the room they show (room_scene.h).

#include <cmath>
#include <cstdint>

#include "drivers/frame_source.h"
#include "tests/openni2/room_scene.h"

namespace sb::test {

// The camera position (the driver's frame count) a millimetre frame shows, read back from the depth of the
// left wall at the left end of the middle row (the wall stays in view for the first ~150 positions).
inline long roomShotOf(const DepthFrame& f) {
  const int w = f.depth.width(), h = f.depth.height();
  const double a = (0 - 0.5 * w) / roomFx(w);
  const double z = f.depth(0, h / 2) / 1000.0;
  return std::lround((kLeft - z * a) / kStepMetres);
}

// Pixels of a millimetre frame that differ from the room rendered at position `shot` by a driver that
// streams `units` per metre (1000, or 10000 converted to millimetres by the source).
inline int roomMismatches(const DepthFrame& f, long shot, double units = 1000.0) {
  const int w = f.depth.width(), h = f.depth.height();
  int bad = 0;
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const uint16_t raw = roomDepthRaw(u, v, w, h, kStepMetres * shot, units);
      const uint16_t expected = units == 1000.0 ? raw : static_cast<uint16_t>((raw + 5) / 10);
      bad += f.depth(u, v) != expected;
    }
  return bad;
}

}  // namespace sb::test
