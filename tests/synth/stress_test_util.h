#pragma once
// What the stress trajectory tests share: speeds and rates between frames, segment peaks, free-space and
// coverage checks, and the views' statistics on a rendered sample of frames.

#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>

#include "controller/surface_detector.h"
#include "synth/renderer.h"
#include "synth/stress_trajectory.h"
#include "synth/stress_views.h"
#include "synth/synth_sequence.h"

namespace sb::synth::stress_test {

constexpr double kFps = 30.0;
constexpr float kClearanceM = 0.15f;  // cameras keep at least this far from walls and furniture
constexpr double kRadToDeg = 180.0 / 3.141592653589793;

// Speed into frame i (from i-1): metres per second and degrees per second.
inline double speedMps(const Trajectory& t, size_t i) {
  return (t[i].position() - t[i - 1].position()).norm() * kFps;
}
inline double rateDegps(const Trajectory& t, size_t i) {
  const Eigen::Matrix3d delta =
      t[i - 1].T_camera_to_world.linear().transpose() * t[i].T_camera_to_world.linear();
  return Eigen::AngleAxisd(delta).angle() * kRadToDeg * kFps;
}

struct Peak {
  double speedMps = 0.0, rateDegps = 0.0;
};
inline Peak peakOf(const Trajectory& t, const StressSegment& s) {
  Peak p;
  for (size_t i = std::max<size_t>(s.begin, 1); i < s.end; ++i) {
    p.speedMps = std::max(p.speedMps, speedMps(t, i));
    p.rateDegps = std::max(p.rateDegps, rateDegps(t, i));
  }
  return p;
}

inline void requireInFreeSpace(const Scene& scene, const Trajectory& t) {
  for (size_t i = 0; i < t.size(); ++i) {
    const Eigen::Vector3f p = t[i].position().cast<float>();
    INFO(scene.name << " seed " << scene.seed << " frame " << i << " at " << p.transpose());
    REQUIRE(scene.insideRoom(p, kClearanceM));
    REQUIRE(scene.objectContaining(p, kClearanceM) < 0);
  }
}

inline void requireCoversFrames(const StressTrajectory& s) {
  REQUIRE_FALSE(s.segments.empty());
  REQUIRE(s.segments.front().begin == 0);
  REQUIRE(s.segments.back().end == s.poses.size());
  for (size_t k = 1; k < s.segments.size(); ++k) REQUIRE(s.segments[k].begin == s.segments[k - 1].end);
  for (size_t i = 0; i < s.poses.size(); ++i) REQUIRE(s.poses[i].timestamp == Approx(i / kFps));
}

// What every stress trajectory must be: 300 to `maxFrames` frames, segments covering every frame in order,
// cameras in the free space of `scene` (the scene it is rendered in).
inline void requireStressShape(const StressTrajectory& s, const Scene& scene, size_t maxFrames = 600) {
  REQUIRE(s.poses.size() >= 300);
  REQUIRE(s.poses.size() <= maxFrames);
  requireCoversFrames(s);
  requireInFreeSpace(scene, s.poses);
}

// A calm segment's peak: slower than 0.2 m/s and 20 deg/s.
inline void requireCalm(const Peak& p) {
  REQUIRE(p.speedMps < 0.2);
  REQUIRE(p.rateDegps < 20.0);
}

inline bool samePoses(const Trajectory& a, const Trajectory& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (!a[i].T_camera_to_world.isApprox(b[i].T_camera_to_world, 1e-12)) return false;
  return true;
}

// Renders every `step`-th frame of [begin, end) at 160x120 with noise; returns the fraction of those frames
// the surface detector calls smooth, and the lowest valid-pixel fraction.
struct ViewStats {
  double smoothFraction = 0.0, lowestValid = 1.0;
  double lowestConstraint = 1e9;  // measureView's minConstraint, the least over the sampled frames
};
inline ViewStats viewStats(const Scene& scene, const Trajectory& t, size_t begin, size_t end, size_t step) {
  constexpr int kScale = 4;
  const Intrinsics k = iclNuimIntrinsics().scaled(kScale);
  const Renderer renderer(scene, k);
  const Renderer coarse(scene, iclNuimIntrinsics().scaled(2 * kScale));
  SurfaceParams surface;
  surface.sampleStridePx = 8 / kScale;  // the default stride of the full-size frame
  DepthMeters meters;
  DepthRaw raw;
  ViewStats stats;
  size_t frames = 0, smooth = 0;
  for (size_t i = begin; i < end; i += step, ++frames) {
    renderer.render(t[i].T_camera_to_world, SensorModel{}, frameSeed(scene.seed, i), meters);
    toRaw(meters, kIclDepthScale, raw);
    smooth += detectSmoothSurface(raw, kIclDepthScale, surface).smooth;
    size_t valid = 0;
    for (float z : meters.pixels()) valid += z > 0.f;
    stats.lowestValid = std::min(stats.lowestValid, static_cast<double>(valid) / meters.size());
    stats.lowestConstraint =
        std::min(stats.lowestConstraint, measureView(coarse, t[i].T_camera_to_world).minConstraint);
  }
  stats.smoothFraction = frames ? static_cast<double>(smooth) / frames : 0.0;
  return stats;
}

}  // namespace sb::synth::stress_test
