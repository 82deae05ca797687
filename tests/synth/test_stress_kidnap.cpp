// The kidnap stresses have their designed shape: calm mapping, 1-3 s covered (and rendered with no depth
// at all), then calm motion; kidnap's first uncovered view is close to a mapping view, 50-70 degrees from
// where the cover went on, and what it sees was seen while mapping; kidnap-unseen's after part sees almost
// nothing a mapping frame saw, while holding structure that would track.

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>

#include "drivers/sequence.h"
#include "synth/renderer.h"
#include "synth/scene_generator.h"
#include "synth/stress_trajectory.h"
#include "synth/stress_views.h"
#include "synth/synth_sequence.h"
#include "tests/support/test_data.h"
#include "tests/synth/stress_test_util.h"

using namespace sb;
using namespace sb::synth;
using namespace sb::synth::stress_test;

namespace {

constexpr int kProbeScale = 8;

double angleDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * kRadToDeg;
}

// The kidnap's parts, checked for order, and the calm of the uncovered ones.
struct Parts {
  StressSegment mapping, covered, after;
};
Parts requireKidnapShape(const StressTrajectory& s, const Scene& scene) {
  requireStressShape(s, scene);
  REQUIRE(s.segments.size() == 3);
  const Parts parts{s.segments[0], s.segments[1], s.segments[2]};
  REQUIRE(parts.mapping.label == "mapping");
  REQUIRE(parts.covered.label == kCoveredLabel);
  REQUIRE(parts.after.label == "after");
  REQUIRE(coveredFrames(s) ==
          std::vector<std::pair<size_t, size_t>>{{parts.covered.begin, parts.covered.end}});
  REQUIRE(parts.mapping.end - parts.mapping.begin >= 8 * kFps);  // ~9 s of mapping
  REQUIRE(parts.covered.end - parts.covered.begin >= 1 * kFps);  // 1-3 s covered
  REQUIRE(parts.covered.end - parts.covered.begin <= 3 * kFps + 1);
  REQUIRE(parts.after.end - parts.after.begin >= 3 * kFps);
  for (const StressSegment& seg : {parts.mapping, parts.after}) {
    const Peak p = peakOf(s.poses, {seg.label, seg.begin + 1, seg.end});
    INFO(seg.label << " [" << seg.begin << ", " << seg.end << "): " << p.speedMps << " m/s, " << p.rateDegps
                   << " deg/s");
    requireCalm(p);
  }
  return parts;
}

SeenSurfaces mappingSeen(const Renderer& renderer, const StressTrajectory& s, const StressSegment& mapping,
                         size_t step) {
  SeenSurfaces seen(renderer);
  for (size_t i = mapping.begin; i < mapping.end; i += step) seen.add(s.poses[i].T_camera_to_world);
  return seen;
}

}  // namespace

TEST_CASE("kidnap: covered 1-3 s, then shown a view close to a mapping view, and it was seen",
          "[synth][stress][kidnap]") {
  for (const std::string& name : sceneNames()) {
    for (uint64_t seed : {0, 1, 2}) {
      const Scene scene = generateScene(name, seed);
      const StressTrajectory s = stressTrajectory(StressKind::Kidnap, scene, seed);
      INFO(name << " seed " << seed << ", " << s.poses.size() << " frames");
      const Parts parts = requireKidnapShape(s, scene);
      // The jump over the covered part: what the tracker sees between its last and next depth frames.
      const Eigen::Isometry3d& before = s.poses[parts.covered.begin - 1].T_camera_to_world;
      const Eigen::Isometry3d& shown = s.poses[parts.after.begin].T_camera_to_world;
      const double jumpM = (shown.translation() - before.translation()).norm(),
                   jumpDeg = angleDeg(before, shown);
      INFO("jump " << jumpM << " m, " << jumpDeg << " deg");
      REQUIRE(jumpM > 0.25);
      REQUIRE(jumpDeg > 40.0);
      REQUIRE(jumpDeg < 80.0);
      // Close to a mapping view seen at least 4 s before the cover went on.
      bool close = false;
      for (size_t i = parts.mapping.begin; i + 4 * kFps < parts.mapping.end; ++i) {
        const Eigen::Isometry3d& m = s.poses[i].T_camera_to_world;
        close = close || ((m.translation() - shown.translation()).norm() < 0.1 && angleDeg(m, shown) < 6.0);
      }
      REQUIRE(close);
      if (seed == 0) {  // what the after part sees was seen while mapping
        const Renderer renderer(scene, iclNuimIntrinsics().scaled(kProbeScale));
        const SeenSurfaces seen = mappingSeen(renderer, s, parts.mapping, 3);
        for (size_t i = parts.after.begin; i < parts.after.end; i += 15) {
          INFO("after frame " << i);
          REQUIRE(seen.seenFraction(s.poses[i].T_camera_to_world) > 0.6);
        }
      }
    }
  }
}

TEST_CASE("kidnap-unseen: after the cover, views no mapping frame saw, that would track",
          "[synth][stress][kidnap]") {
  const StressParams params;
  for (const std::string& name : sceneNames()) {
    for (uint64_t seed : {0, 1, 2}) {
      const Scene scene = generateScene(name, seed);
      const StressTrajectory s = stressTrajectory(StressKind::KidnapUnseen, scene, seed);
      INFO(name << " seed " << seed << ", " << s.poses.size() << " frames");
      const Parts parts = requireKidnapShape(s, scene);
      const Renderer renderer(scene, iclNuimIntrinsics().scaled(kProbeScale));
      // Checked against every other mapping frame (the generator used every third).
      const SeenSurfaces seen = mappingSeen(renderer, s, parts.mapping, 2);
      double worst = 0.0;
      for (size_t i = parts.after.begin; i < parts.after.end; i += 6) {
        INFO("after frame " << i);
        const Eigen::Isometry3d& T = s.poses[i].T_camera_to_world;
        worst = std::max(worst, seen.seenFraction(T));
        const ViewMetrics m = measureView(renderer, T);
        REQUIRE(m.validFraction > 0.8);
        REQUIRE(m.minConstraint > 0.005);
      }
      INFO("largest seen fraction " << worst);
      REQUIRE(worst <= params.kidnapMaxSeenFraction);
    }
  }
}

TEST_CASE("kidnap: covered frames are written with no depth, the others with depth",
          "[synth][stress][kidnap]") {
  const Scene scene = generateScene("livingroom", 1);
  const StressTrajectory s = stressTrajectory(StressKind::Kidnap, scene, 1);
  const std::string dir = test::scratchDir("synth_kidnap_covered");
  SynthOptions options;
  options.outDir = dir;
  options.overwrite = true;
  options.seed = 1;
  options.intrinsics = iclNuimIntrinsics().scaled(kProbeScale);  // 80x60 keeps the test fast
  options.coveredFrames = coveredFrames(s);
  const SynthResult r = synthesizeSequence(scene, s.poses, options);
  REQUIRE(r.frames == s.poses.size());
  const auto [coveredBegin, coveredEnd] = options.coveredFrames.at(0);
  auto source = openSequence(dir);
  for (size_t i = 0; i < s.poses.size(); ++i) {
    const auto frame = source->next();
    REQUIRE(frame);
    size_t valid = 0;
    for (uint16_t v : frame->depth.pixels()) valid += v != 0;
    INFO("frame " << i << ": " << valid << " of " << frame->depth.size() << " pixels with depth");
    if (i >= coveredBegin && i < coveredEnd)
      REQUIRE(valid == 0);
    else
      REQUIRE(valid > frame->depth.size() / 2);
  }
}
