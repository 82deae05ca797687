#include "pipeline/bilateral_taps.h"

#include <cmath>

namespace sb {

BilateralTaps bilateralTaps(const PipelineConfig& config) {
  BilateralTaps taps;
  taps.radius = config.bilateralRadius;
  const float sigma = config.bilateralSpatialSigma;
  for (int i = -taps.radius; i <= taps.radius; ++i)
    taps.weights.push_back(std::exp(-static_cast<float>(i * i) / (2.0f * sigma * sigma)));
  return taps;
}

}  // namespace sb
