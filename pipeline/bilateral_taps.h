#pragma once
// The bilateral filter's spatial taps: the config's radius and sigma in the compute size's own pixels, at every
// compute size (KinectFusion's filter on whatever image it is given). A coarse image is so smoothed over csr times
// the sensor area; taps in sensor pixels instead were measured and removed (docs/performance-history.md, "Switches
// removed").

#include <vector>

#include "pipeline/config.h"

namespace sb {

struct BilateralTaps {
  int radius = 0;              // image pixels at the compute size
  std::vector<float> weights;  // 2 radius + 1: exp(-i^2 / (2 sigma^2)), sigma in image pixels
};

BilateralTaps bilateralTaps(const PipelineConfig& config);

}  // namespace sb
