#pragma once
// The bilateral filter's spatial taps at a compute size ratio. By default the config's radius and sigma are in the
// compute size's own pixels (KinectFusion's filter on whatever image it is given). With bilateral_sensor_footprint
// they are in sensor pixels: at ratio csr the taps are ceil(radius / csr) and sigma / csr image pixels, so the filter
// covers the same part of the sensor at every compute size (at csr 1 the same taps, bit for bit). Without it a
// coarse image is smoothed over csr times the sensor area: at csr 2 its 5x5 taps span 10x10 sensor pixels, and the
// floor's depth, convex across the rows, comes out biased (the corridor drive's camera tilted by about 1 degree over
// 17 m); but on real Kinect data the wider smoothing is worth more than the bias (docs/odometry.md).

#include <vector>

#include "pipeline/config.h"

namespace sb {

struct BilateralTaps {
  int radius = 0;              // image pixels at the compute size
  std::vector<float> weights;  // 2 radius + 1: exp(-i^2 / (2 sigma^2)), sigma in image pixels
};

BilateralTaps bilateralTaps(const PipelineConfig& config, int csr);

}  // namespace sb
