#include "drivers/camera_bounds.h"

#include <algorithm>
#include <sstream>

#include "core/error.h"

namespace sb {

std::vector<CameraBound> cameraBounds(const Intrinsics& k, std::optional<double> depthScale, size_t maxPixels) {
  const double side = std::max(k.width, k.height);
  const double pixels = double(k.width) * double(k.height);
  std::vector<CameraBound> bounds = {
      {"width", double(k.width), kMinDepthImageSide, kMaxDepthImageSide, "pixels",
       "the pipeline's 3-level pyramid needs 8, allocations are bounded at 4096"},
      {"height", double(k.height), kMinDepthImageSide, kMaxDepthImageSide, "pixels",
       "the pipeline's 3-level pyramid needs 8, allocations are bounded at 4096"},
      {"width x height", pixels, 0, maxPixels > 0 ? double(maxPixels) : pixels, "pixels",
       "source.max_frame_pixels, the largest frame configured"},
      {"fx", k.fx, side / 100, side * 100, "pixels", "a field of view between about 1 and 179 degrees"},
      {"fy", k.fy, side / 100, side * 100, "pixels", "a field of view between about 1 and 179 degrees"},
      {"cx", k.cx, -double(k.width), 2.0 * k.width, "pixels", "the principal point lies near the image centre"},
      {"cy", k.cy, -double(k.height), 2.0 * k.height, "pixels", "the principal point lies near the image centre"},
  };
  if (depthScale)
    bounds.push_back({"depth_scale", *depthScale, kMinDepthScale, kMaxDepthScale, "raw units per metre",
                      "1000 for millimetres, 5000 for TUM"});
  return bounds;
}

std::optional<CameraBound> cameraOutOfBounds(const Intrinsics& k, std::optional<double> depthScale,
                                             size_t maxPixels) {
  for (const CameraBound& b : cameraBounds(k, depthScale, maxPixels))
    if (!(b.value >= b.lo && b.value <= b.hi)) return b;  // NaN fails too
  return std::nullopt;
}

std::string cameraBoundMessage(const std::string& origin, const CameraBound& b, const Intrinsics& k) {
  std::ostringstream msg;
  msg << origin << ": " << b.name << " = " << b.value << " " << b.unit << " is not plausible for a " << k.width
      << "x" << k.height << " image; expected " << b.name << " in [" << b.lo << ", " << b.hi << "] (" << b.why
      << ")";
  return msg.str();
}

void checkCameraBounds(const std::string& origin, const Intrinsics& k, std::optional<double> depthScale,
                       size_t maxPixels) {
  if (const auto bound = cameraOutOfBounds(k, depthScale, maxPixels))
    throw Error(cameraBoundMessage(origin, *bound, k));
}

}  // namespace sb
