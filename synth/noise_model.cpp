#include "synth/noise_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sb::synth {

namespace {

constexpr double kTwoPi = 6.283185307179586;
constexpr double kDegToRad = 3.141592653589793 / 180.0;
constexpr uint64_t kGolden = 0x9E3779B97F4A7C15ull;

uint64_t splitmix64(uint64_t x) {
  x += kGolden;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// Uniform in (0, 1] from the top 53 bits.
double unitOpen(uint64_t bits) { return (static_cast<double>(bits >> 11) + 1.0) * (1.0 / 9007199254740992.0); }

// One standard normal sample for pixel `index` of the frame with `seed` (Box-Muller).
double gaussian(uint64_t seed, uint64_t index) {
  const uint64_t h1 = splitmix64(seed ^ (index * kGolden));
  const uint64_t h2 = splitmix64(h1);
  return std::sqrt(-2.0 * std::log(unitOpen(h1))) * std::cos(kTwoPi * unitOpen(h2));
}

bool nearDiscontinuity(const Image<float>& depth, int x, int y, float z, const SensorModel& m) {
  const float jump = static_cast<float>(m.edgeJumpM + m.edgeJumpRatio * z);
  for (int dy = -m.edgeRadiusPx; dy <= m.edgeRadiusPx; ++dy) {
    const int yy = y + dy;
    if (yy < 0 || yy >= depth.height()) continue;
    for (int dx = -m.edgeRadiusPx; dx <= m.edgeRadiusPx; ++dx) {
      const int xx = x + dx;
      if (xx < 0 || xx >= depth.width()) continue;
      const float zn = depth(xx, yy);
      if (zn <= 0.f || std::abs(zn - z) > jump) return true;  // nothing hit next to a surface is an edge too
    }
  }
  return false;
}

}  // namespace

uint64_t frameSeed(uint64_t baseSeed, uint64_t frameIndex) {
  return splitmix64(splitmix64(baseSeed) + frameIndex);
}

void applySensorModel(const IdealFrame& ideal, const SensorModel& m, double fPx, uint64_t seed, int rowBegin,
                      int rowEnd, DepthMeters& out) {
  const int w = ideal.depthM.width();
  const double bf = m.baselineM * fPx;  // pixel-metres
  const float minCos = static_cast<float>(std::cos(m.maxIncidenceDeg * kDegToRad));
  for (int y = rowBegin; y < rowEnd; ++y) {
    for (int x = 0; x < w; ++x) {
      const float z = ideal.depthM(x, y);
      double measured = z;
      if (z > 0.f && m.noise) {
        if (ideal.cosIncidence(x, y) < minCos || nearDiscontinuity(ideal.depthM, x, y, z, m)) {
          measured = 0.0;
        } else {
          const uint64_t index = static_cast<uint64_t>(y) * w + x;
          double disparity = bf / z + m.sigmaDisparityPx * gaussian(seed, index);
          if (m.disparityStepPx > 0.0) disparity = std::round(disparity / m.disparityStepPx) * m.disparityStepPx;
          measured = disparity > 0.0 ? bf / disparity : 0.0;
        }
      }
      // The sensor sees nothing outside its range, and reports nothing that measures outside it.
      const bool inRange = z >= m.minDepthM && z <= m.maxDepthM;
      if (!inRange || measured < m.minDepthM || measured > m.maxDepthM) measured = 0.0;
      out(x, y) = static_cast<float>(measured);
    }
  }
}

void toRaw(const DepthMeters& meters, double depthScale, DepthRaw& out) {
  out.resize(meters.width(), meters.height());
  const double maxRaw = std::numeric_limits<uint16_t>::max() - 1;  // 65535 is "invalid" in some formats
  for (size_t i = 0; i < meters.size(); ++i) {
    const double raw = std::round(meters.data()[i] * depthScale);
    out.data()[i] = (raw <= 0.0 || raw > maxRaw) ? 0 : static_cast<uint16_t>(raw);
  }
}

}  // namespace sb::synth
