#pragma once
// One set of bounds for a depth camera, whichever door it comes through (issue 44 P7, G3): calibration.json
// and the command line (drivers/calibration.h checkIntrinsics), a pushed frame's header (the daemon's push
// source) and a bag's CameraInfo (drivers/bag_loader.cpp). Each refusal has one shape:
//   "<origin>: fx = 1e-30 pixels is not plausible for a 640x480 image; expected fx in [6.4, 64000] (...)".

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/intrinsics.h"

namespace sb {

// Smallest depth-image side: the pipeline's 3-level pyramid needs 2 pixels per side at its coarsest level.
constexpr int kMinDepthImageSide = 8;
// Plausible depth scales, raw units per metre: 100 (centimetres) to 100000 (10 micrometres, a 0.65 m range in
// 16 bits). 1000 (millimetres) and 5000 (TUM) are the usual ones.
constexpr double kMinDepthScale = 100.0;
constexpr double kMaxDepthScale = 100000.0;

// One value's bounds, as the message gives them.
struct CameraBound {
  const char* name;  // "fx", "width", "depth_scale", ...
  double value, lo, hi;
  const char* unit;  // "pixels", "raw units per metre"
  const char* why;   // the reason of the range, in parentheses
};

// Every bound: width, height, width x height, fx, fy, cx, cy, and depth_scale when given.
std::vector<CameraBound> cameraBounds(const Intrinsics& k, std::optional<double> depthScale, size_t maxPixels = 0);

// The first value of `k` (size, then fx, fy, cx, cy) or of `depthScale` (when given) outside its bounds, or
// nothing. `maxPixels` (0: no limit beyond kMaxDepthImageSide per side) bounds width x height.
std::optional<CameraBound> cameraOutOfBounds(const Intrinsics& k, std::optional<double> depthScale,
                                             size_t maxPixels = 0);

// The message of a refused value: "<origin>: <name> = <value> <unit> is not plausible for a WxH image;
// expected <name> in [lo, hi] (<why>)".
std::string cameraBoundMessage(const std::string& origin, const CameraBound& bound, const Intrinsics& k);

// Throws sb::Error with cameraBoundMessage when cameraOutOfBounds finds a value.
void checkCameraBounds(const std::string& origin, const Intrinsics& k, std::optional<double> depthScale,
                       size_t maxPixels = 0);

}  // namespace sb
