// The pairs a far view can check (pipeline/pair_noise.h): tolerances widened to the depth sensor's noise at each
// pixel's range, never tighter than tracking's; CpuBackend's count of a track pass's pairs under them
// (countPairsInNoise) against tracking's fixed tests on the same pairs.

#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "kernels/track.h"
#include "pipeline/cpu/cpu_track.h"
#include "pipeline/pair_noise.h"

namespace {

// The synthetic sensor at 160x120 (synth/noise_model.h): 0.05 px of disparity noise and 1/8 px steps give
// sqrt(0.05^2 + 0.125^2 / 12) = 0.062 px; baseline 0.075 m; f = 120.3 px.
sb::DepthNoiseModel synthSensor() { return sb::DepthNoiseModel{0.062, 0.075, 120.3}; }

}  // namespace

TEST_CASE("pair tolerances follow the structured-light noise z^2 sigma_d / (b f), floored at tracking's") {
  const sb::DepthNoiseModel m = synthSensor();
  CHECK(m.sigmaM(3.0) == Approx(9.0 * 0.062 / (0.075 * 120.3)));
  CHECK(m.sigmaM(2.0) == Approx(m.sigmaM(1.0) * 4.0));

  // Off (no noise given): tracking's tests, whatever the range.
  const sb::PairTolerance off = sb::pairTolerance(sb::DepthNoiseModel{}, 4.0, 60.0, 0.1f, 0.8f);
  CHECK(off.distanceM == 0.1f);
  CHECK(off.normalCos == 0.8f);

  // Near: three standard deviations of two readings (1 cm at 0.8 m) are within tracking's 0.1 m.
  const sb::PairTolerance near = sb::pairTolerance(m, 0.8, 60.0, 0.1f, 0.8f);
  CHECK(near.distanceM == 0.1f);

  // Far: 3 sqrt(2) sigma_z, 0.36 m at 3.5 m.
  const sb::PairTolerance far = sb::pairTolerance(m, 3.5, 60.0, 0.1f, 0.8f);
  CHECK(far.distanceM == Approx(3.0 * std::sqrt(2.0) * m.sigmaM(3.5)).epsilon(1e-6));
  CHECK(far.distanceM > 0.3f);

  // The normal test widens with the tilt that the depth noise gives central differences 2 pixels apart, never
  // beyond 90 degrees (normals facing away always fail) and never tighter than tracking's.
  double previous = 1.0;
  for (double z = 0.5; z <= 4.5; z += 0.5) {
    const sb::PairTolerance t = sb::pairTolerance(m, z, 60.0, 0.1f, 0.8f);
    CHECK(t.normalCos <= 0.8f);
    CHECK(t.normalCos >= -1e-6f);
    CHECK(t.normalCos <= previous + 1e-6);
    CHECK(t.distanceM >= 0.1f);
    previous = t.normalCos;
  }
  // A finer level (larger focal length, smaller footprint) tilts more for the same depth noise.
  CHECK(sb::pairTolerance(m, 1.0, 120.0, 0.1f, 0.99f).normalCos < sb::pairTolerance(m, 1.0, 30.0, 0.1f, 0.99f).normalCos);
}

TEST_CASE("a far pair off by the sensor's noise agrees within the noise, a near one off as much does not") {
  // Four pixels of a 4x1 input level (f = 60 px, identity poses): two on a wall 1 m away, two on a wall 3.5 m
  // away, each read 0.15 m too far along its ray; the model's surface is where the walls are. Tracking's fixed
  // test (0.1 m) rejects all four; within the noise (0.36 m at 3.5 m, 0.1 m at 1 m) the two far ones agree.
  const int w = 4;
  const double f = 60.0, cx = 1.5, cy = 0.0;
  const double depth[w] = {1.0, 1.0, 3.5, 3.5};
  std::vector<float> vertex(3 * w), normal(3 * w), refVertex(3 * w), refNormal(3 * w);
  for (int x = 0; x < w; ++x) {
    const double rx = (x - cx) / f;
    const double measured = depth[x] + 0.15;
    vertex[3 * x] = float(rx * measured);
    vertex[3 * x + 1] = 0.0f;
    vertex[3 * x + 2] = float(measured);
    refVertex[3 * x] = float(rx * depth[x]);
    refVertex[3 * x + 1] = 0.0f;
    refVertex[3 * x + 2] = float(depth[x]);
    for (std::vector<float>* n : {&normal, &refNormal}) {
      (*n)[3 * x] = 0.0f;
      (*n)[3 * x + 1] = 0.0f;
      (*n)[3 * x + 2] = -1.0f;
    }
  }
  sb::TrackInputs in;
  in.vertex = vertex.data();
  in.normal = normal.data();
  in.width = w;
  in.height = 1;
  in.refVertex = refVertex.data();
  in.refNormal = refNormal.data();
  in.refWidth = w;
  in.refHeight = 1;
  const float identity[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  const float project[12] = {float(f), 0, float(cx), 0, 0, float(f), float(cy), 0, 0, 0, 1, 0};
  for (int i = 0; i < 12; ++i) {
    in.cameraToWorld.m[i] = identity[i];
    in.worldToRefPixel.m[i] = project[i];
  }
  in.distanceThreshold = 0.1f;
  in.normalThreshold = 0.8f;

  sb::TrackBand band;
  sb::trackBand(in, 0, 1, band);
  CHECK(band.inliers == 0);
  CHECK(band.tooFar == 4);

  const sb::PairCounts noisy = sb::countPairsInNoise(in, synthSensor(), f);
  CHECK(noisy.agreeing == 2.0);
  CHECK(noisy.failing == 2.0);
  CHECK(noisy.agreement() == Approx(0.5));

  // Without a noise model the count is tracking's.
  const sb::PairCounts fixed = sb::countPairsInNoise(in, sb::DepthNoiseModel{}, f);
  CHECK(fixed.agreeing == 0.0);
  CHECK(fixed.failing == 4.0);
}
