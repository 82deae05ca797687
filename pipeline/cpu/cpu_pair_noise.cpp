// CpuBackend::pairsInNoise (pipeline/pair_noise.h): the last track pass's pairs, each tested by kernels/track.h's
// track() with its own tolerances. Scalar: it runs once per relocalisation attempt, at the tracked level.
#include <chrono>
#include <vector>

#include "core/error.h"
#include "kernels/track.h"
#include "pipeline/cpu/cpu_backend.h"

namespace sb {

PairCounts countPairsInNoise(const TrackInputs& in, const DepthNoiseModel& model, double levelFocalPx) {
  PairCounts counts;
  std::vector<float> out(static_cast<size_t>(in.width) * in.height * SB_TRACK_STRIDE);  // track()'s layout
  for (int y = 0; y < in.height; ++y) {
    for (int x = 0; x < in.width; ++x) {
      const size_t index = static_cast<size_t>(y) * in.width + x;
      const float z = in.vertex[3 * index + 2];
      const PairTolerance t = pairTolerance(model, z, levelFocalPx, in.distanceThreshold, in.normalThreshold);
      track(out.data(), in.vertex, in.normal, in.width, in.refVertex, in.refNormal, in.refWidth, in.refHeight,
            in.cameraToWorld, in.worldToRefPixel, t.distanceM, t.normalCos, x, y);
      const float result = out[SB_TRACK_STRIDE * index];
      if (result == SB_TRACK_INLIER) counts.agreeing += 1.0;
      if (result == SB_TRACK_TOO_FAR || result == SB_TRACK_BAD_NORMAL) counts.failing += 1.0;
    }
  }
  return counts;
}

std::optional<PairCounts> CpuBackend::pairsInNoise(const DepthNoiseModel& model, StageTimes& times) {
  if (!hasTrack_) throw Error("CpuBackend::pairsInNoise called without a track since the last preprocess or raycast");
  const auto start = std::chrono::steady_clock::now();
  const PairCounts counts = countPairsInNoise(lastTrack_, model, levels_[lastTrackLevel_].k.fx);
  times[Stage::track] += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return counts;
}

}  // namespace sb
