#pragma once
// The pairs a far view can check (issue 55): a relocalisation candidate's pair agreement with each pair's
// distance and normal tests widened to the depth sensor's noise at that pixel's range.
//
// Tracking's pair tests (icp_distance_threshold_m, icp_normal_threshold) are fixed. A structured-light sensor's
// depth noise grows with the square of the range: it measures the disparity d = b f / z (b: baseline, f: focal
// length in the sensor image's pixels) with a noise of sigma_d pixels (its own noise and its quantisation), so
// sigma_z(z) = z^2 sigma_d / (b f) (synth/noise_model.h renders exactly this; Kinect v1: sigma_d about 0.06 px at
// f = 580 px, 1.4 cm at 3 m). Far enough away the fixed tests fail right pairs on noise alone, and a view whose
// most pairs lie there cannot reach a relocaliser's bar even placed right. Here each pair is tested against
//   distance: max(icp distance threshold, k sqrt(2) sigma_z(z))   (two readings of the surface: the frame's and
//             the model's, each at most one reading's noise);
//   normal:   the angle max(acos(icp normal threshold), k sqrt(2) atan(sigma_z(z) / (sqrt(2) s))), at most 90 deg
//             (the normal is the cross product of central differences 2 s apart, s = z / f_level the pixel's
//             footprint at the tracked level: the depth difference's noise sqrt(2) sigma_z tilts it by about
//             atan(sqrt(2) sigma_z / (2 s)); two normals, the frame's and the model's);
// with k = 3 (three standard deviations), z the input pixel's depth. No bilateral filtering is credited: its
// gain on structured-light depth is not that of independent noise (the disparity quantisation leaves terraces
// that the filter's range weight keeps), so the widened tests are an upper bound of the noise, never tighter
// than tracking's. The tracking path's pair agreement (FrameResult::pairAgreement, read by the odometry's fault
// watch) is unchanged; this is a second count, for the relocaliser only (TrackAttempt::agreementInNoise).

#include <algorithm>
#include <cmath>

namespace sb {

struct DepthNoiseModel {
  double disparityNoisePx = 0.0;  // sigma_d, the sensor image's pixels (0: off, tracking's fixed tests)
  double baselineM = 0.075;       // b, metres
  double focalPx = 0.0;           // f, the sensor image's pixels (its fx)
  bool on() const { return disparityNoisePx > 0.0 && baselineM > 0.0 && focalPx > 0.0; }
  // Standard deviation of a depth reading at z metres.
  double sigmaM(double z) const { return on() ? z * z * disparityNoisePx / (baselineM * focalPx) : 0.0; }
};

struct PairTolerance {
  float distanceM = 0.0f;  // a pair farther apart fails
  float normalCos = 1.0f;  // a pair whose normals' dot product is lower fails
};

// The tests of a pair whose input pixel lies at depth `z` metres, at a tracked level of focal length
// `levelFocalPx` (the sensor's f / (csr 2^level)); tracking's thresholds are the floor.
inline PairTolerance pairTolerance(const DepthNoiseModel& m, double z, double levelFocalPx, float distanceThreshold,
                                   float normalThreshold) {
  constexpr double kSigmas = 3.0;
  constexpr double kHalfPi = 1.5707963267948966;
  PairTolerance t{distanceThreshold, normalThreshold};
  if (!m.on() || !(z > 0.0) || !(levelFocalPx > 0.0)) return t;
  const double sigma = m.sigmaM(z);
  t.distanceM = static_cast<float>(std::max(double(distanceThreshold), kSigmas * std::sqrt(2.0) * sigma));
  const double footprint = z / levelFocalPx;
  const double tilt = std::atan(sigma / (std::sqrt(2.0) * footprint));
  const double fixedAngle = std::acos(std::max(-1.0, std::min(1.0, double(normalThreshold))));
  const double angle = std::min(kHalfPi, std::max(fixedAngle, kSigmas * std::sqrt(2.0) * tilt));
  t.normalCos = static_cast<float>(std::min(double(normalThreshold), std::cos(angle)));
  return t;
}

// Pairs of one ICP pass tested with pairTolerance: those agreeing, and those with a model surface that fail.
struct PairCounts {
  double agreeing = 0.0;
  double failing = 0.0;
  double agreement() const { return agreeing + failing > 0.0 ? agreeing / (agreeing + failing) : 0.0; }
};

}  // namespace sb
