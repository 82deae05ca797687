#pragma once
// Smooth-surface detection on the raw depth frame (architecture.md D4): a view of one smooth surface (a blank
// wall, a floor seen head-on) gives ICP little to hold on to, so the controller raises precision. Four
// quadrant windows inside a margin are sampled on a fixed grid of the full-size frame (so the sample count
// does not depend on csr); a window is flat when the std of its valid depths is below the threshold and
// enough of its samples are valid. The view is smooth when all four windows are flat.

#include <array>

#include "core/config_reader.h"
#include "core/image.h"

namespace sb {

struct SurfaceParams {
  double marginFraction = 0.1;     // of the width / height, left out on every side
  int sampleStridePx = 8;          // grid step in full-size pixels (8 = every pixel at the coarsest csr)
  double stdThresholdM = 0.14;     // metres: a window is flat below this std (original OpenCL: 0.14 m)
  double minValidFraction = 0.5;   // a window with fewer valid samples is not flat (no evidence)

  // Keys: surface_margin_fraction, surface_sample_stride_px, surface_std_threshold_m, surface_min_valid_fraction.
  void read(ConfigReader& reader);
  void toJson(nlohmann::json& section) const;  // adds the same keys with their values
};

struct SurfaceResult {
  bool smooth = false;
  std::array<double, 4> stdM{};   // per window (top-left, top-right, bottom-left, bottom-right), metres
  std::array<int, 4> valid{};     // valid samples per window
  int samplesPerWindow = 0;
};

// `depthScale`: raw units per metre.
SurfaceResult detectSmoothSurface(const DepthRaw& depth, double depthScale, const SurfaceParams& params);

}  // namespace sb
