#include "controller/surface_detector.h"

#include <cmath>

namespace sb {

void SurfaceParams::read(ConfigReader& r) {
  r.number("surface_margin_fraction", marginFraction, 0.0, 0.45);
  r.integer("surface_sample_stride_px", sampleStridePx, 1, 64);
  r.number("surface_std_threshold_m", stdThresholdM, 0.0, 10.0);
  r.number("surface_min_valid_fraction", minValidFraction, 0.0, 1.0);
}

void SurfaceParams::toJson(nlohmann::json& j) const {
  j["surface_margin_fraction"] = marginFraction;
  j["surface_sample_stride_px"] = sampleStridePx;
  j["surface_std_threshold_m"] = stdThresholdM;
  j["surface_min_valid_fraction"] = minValidFraction;
}

SurfaceResult detectSmoothSurface(const DepthRaw& depth, double depthScale, const SurfaceParams& p) {
  SurfaceResult result;
  const int w = depth.width(), h = depth.height();
  const int x0 = static_cast<int>(p.marginFraction * w), x1 = w - x0;
  const int y0 = static_cast<int>(p.marginFraction * h), y1 = h - y0;
  const int midX = (x0 + x1) / 2, midY = (y0 + y1) / 2;
  const int s = p.sampleStridePx;
  bool allFlat = w > 0 && h > 0;
  for (int window = 0; window < 4; ++window) {
    const int wx0 = window % 2 ? midX : x0, wx1 = window % 2 ? x1 : midX;
    const int wy0 = window / 2 ? midY : y0, wy1 = window / 2 ? y1 : midY;
    double sum = 0, sumSq = 0;
    int valid = 0, samples = 0;
    for (int y = wy0 + s / 2; y < wy1; y += s) {
      for (int x = wx0 + s / 2; x < wx1; x += s) {
        ++samples;
        const uint16_t raw = depth(x, y);
        if (raw == 0) continue;
        const double z = raw / depthScale;
        sum += z;
        sumSq += z * z;
        ++valid;
      }
    }
    const double mean = valid ? sum / valid : 0.0;
    const double variance = valid ? std::max(0.0, sumSq / valid - mean * mean) : 0.0;
    result.stdM[window] = std::sqrt(variance);
    result.valid[window] = valid;
    result.samplesPerWindow = samples;
    const bool enough = samples > 0 && valid >= p.minValidFraction * samples && valid > 0;
    allFlat = allFlat && enough && result.stdM[window] < p.stdThresholdM;
  }
  result.smooth = allFlat;
  return result;
}

}  // namespace sb
