// OpenClBackend::pairsInNoise (pipeline/pair_noise.h): the last track pass's maps (its input level's vertices
// and normals, the reference maps) read back as float, with the pass's transforms and thresholds, and counted
// on the host by the CPU backend's countPairsInNoise (pipeline/cpu/cpu_pair_noise.cpp: kernels/track.h's
// track() per pixel with pairTolerance's tolerances). So the widened tests have one definition (in double, as
// on the CPU) and the count is the CPU backend's on the device's own maps. It runs once per view a
// relocaliser checks, not per frame: 4 maps read back (3.7 MB at 320x240 tracked at level 0, float or half
// storage alike) and one scalar pass on the host. Measured on PoCL (2-core x86, 2026-12-07), 320x240 at level
// 0: 9-10 ms (float storage; half 10.5-11 ms), of which the scalar pass 5.5-7 ms (the CPU backend's whole
// cost); one track + reduce pass on the device 5.5-6.5 ms. At 160x120 (the relocaliser's csr 2): 2 ms.
#include <chrono>
#include <vector>

#include "core/error.h"
#include "pipeline/cpu/cpu_track.h"
#include "pipeline/opencl/device_state.h"

namespace sb {

std::optional<PairCounts> OpenClBackend::pairsInNoise(const DepthNoiseModel& model, StageTimes& times) {
  State& s = *s_;
  if (!s.hasTrack)
    throw Error("OpenClBackend::pairsInNoise called without a track since the last preprocess or raycast");
  const auto start = std::chrono::steady_clock::now();
  const State::Level& level = s.levels.at(s.trackLevel);
  // readMap waits for the queue (the track pass included) and converts half storage to float on the device.
  const std::vector<float> vertex = s.readMap(level.vertex, 3 * State::pixels(level.k, true));
  const std::vector<float> normal = s.readMap(level.normal, 3 * State::pixels(level.k, true));
  const std::vector<float> refVertex = s.readMap(s.referenceVertex, 3 * State::pixels(s.referenceK, true));
  const std::vector<float> refNormal = s.readMap(s.referenceNormal, 3 * State::pixels(s.referenceK, true));
  TrackInputs in;
  in.vertex = vertex.data();
  in.normal = normal.data();
  in.width = level.k.width;
  in.height = level.k.height;
  in.refVertex = refVertex.data();
  in.refNormal = refNormal.data();
  in.refWidth = s.referenceK.width;
  in.refHeight = s.referenceK.height;
  in.cameraToWorld = s.trackCameraToWorld;
  in.worldToRefPixel = s.trackWorldToRefPixel;
  in.distanceThreshold = s.config.icpDistanceThreshold;
  in.normalThreshold = s.config.icpNormalThreshold;
  const PairCounts counts = countPairsInNoise(in, model, level.k.fx);
  times[Stage::track] +=
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return counts;
}

}  // namespace sb
