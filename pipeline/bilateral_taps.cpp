#include "pipeline/bilateral_taps.h"

#include <cmath>

namespace sb {

BilateralTaps bilateralTaps(const PipelineConfig& config, int csr) {
  const int ratio = config.bilateralSensorFootprint && csr > 1 ? csr : 1;
  BilateralTaps taps;
  taps.radius = (config.bilateralRadius + ratio - 1) / ratio;
  const float sigma = config.bilateralSpatialSigma / static_cast<float>(ratio);
  for (int i = -taps.radius; i <= taps.radius; ++i)
    taps.weights.push_back(std::exp(-static_cast<float>(i * i) / (2.0f * sigma * sigma)));
  return taps;
}

}  // namespace sb
