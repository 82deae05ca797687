// The corridor scene and the drive: the corridor has its seeded structure on both walls and a clear middle;
// the robot drives its length (less 1.5 m at each end) at a steady 1-1.5 m/s, U-turns under 45 deg/s and
// drives back, at a fixed height, pitch and roll, its body clear of everything; the volume hint holds the
// whole path.

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>

#include "core/error.h"
#include "synth/corridor_scene.h"
#include "synth/scene_generator.h"
#include "synth/stress_trajectory.h"
#include "synth/synth_sequence.h"
#include "synth/volume_hints.h"
#include "tests/synth/stress_test_util.h"

using namespace sb;
using namespace sb::synth;
using namespace sb::synth::stress_test;

TEST_CASE("corridor: seeded structure on both walls, a clear middle", "[synth][stress][drive]") {
  const CorridorParams params;
  std::map<std::string, int> allKinds;  // over the seeds
  for (uint64_t seed : {0, 1, 2}) {
    const Scene scene = generateCorridor(seed);
    INFO("seed " << seed);
    REQUIRE(scene.name == kCorridorSceneName);
    REQUIRE(scene.roomMax.z() - scene.roomMin.z() == Approx(20.0));
    REQUIRE(scene.roomMax.y() - scene.roomMin.y() == Approx(2.6));
    std::map<std::string, int> kinds;
    for (const Primitive& p : scene.primitives) ++kinds[p.label], ++allKinds[p.label];
    for (const char* kind : {"wall", "pipe", "light"}) {
      INFO(kind);
      REQUIRE(kinds[kind] > 0);
    }
    // Across the walls: gaps (doors or openings) and things standing out of them, several of each.
    REQUIRE(kinds["wall"] >= 4);
    REQUIRE(kinds["pillar"] + kinds["cabinet"] + kinds["riser"] >= 4);
    // Nothing but air within the clear half-width of the axis, floor to ceiling, end to end.
    for (float z = 0.05f; z < 20.f; z += 0.1f)
      for (float x = -static_cast<float>(params.clearHalfWidthM); x <= params.clearHalfWidthM; x += 0.1f)
        for (float y = scene.roomMin.y() + 0.2f; y < scene.roomMax.y() - 0.02f; y += 0.2f) {
          const int hit = scene.objectContaining(Eigen::Vector3f(x, y, z));
          INFO("at " << x << ", " << y << ", " << z << ": " << (hit >= 0 ? scene.primitives[hit].label : ""));
          REQUIRE(hit < 0);
        }
    // Walls 2.2 m apart where there is wall.
    REQUIRE(scene.objectContaining(Eigen::Vector3f(1.15f, 0.f, 0.05f)) >= 0);
  }
  for (const char* kind : {"door", "lintel", "pillar", "cabinet", "riser", "alcove.box"}) {
    INFO(kind);
    REQUIRE(allKinds[kind] > 0);
  }
  REQUIRE_THROWS_AS(generateCorridor(0, CorridorParams{2.0}), Error);
  REQUIRE(generateCorridor(0, CorridorParams{40.0}).roomMax.z() == Approx(40.0));
  // Sparser structure: fewer features, the same clear middle.
  CorridorParams sparse;
  sparse.spacingScale = 5.0;
  const Scene dense = generateCorridor(0), thin = generateCorridor(0, sparse);
  INFO(dense.primitives.size() << " primitives at spacing 1, " << thin.primitives.size() << " at 5");
  REQUIRE(thin.primitives.size() * 3 < dense.primitives.size() * 2);
  REQUIRE(thin.objectContaining(Eigen::Vector3f(0.6f, 0.f, 10.f)) < 0);
  sparse.spacingScale = 0.1;
  REQUIRE_THROWS_AS(generateCorridor(0, sparse), Error);
}

TEST_CASE("drive: 17 m out and back at 1-1.5 m/s, a slow U-turn, clear of everything",
          "[synth][stress][drive]") {
  const StressParams params;
  for (uint64_t seed : {0, 1, 2}) {
    const Scene scene = generateCorridor(seed);
    const StressTrajectory s = stressTrajectory(StressKind::Drive, scene, seed);
    INFO("seed " << seed << ", " << s.poses.size() << " frames");
    requireCoversFrames(s);
    requireInFreeSpace(scene, s.poses);
    REQUIRE(s.segments.size() == 7);
    const char* labels[] = {"accelerate", "drive", "brake", "turn", "accelerate", "drive", "brake"};
    for (size_t k = 0; k < 7; ++k) REQUIRE(s.segments[k].label == labels[k]);
    const double height = scene.roomMax.y() - params.driveCameraHeightM;
    for (size_t i = 0; i < s.poses.size(); ++i) {
      const Eigen::Matrix3d R = s.poses[i].T_camera_to_world.linear();
      const Eigen::Vector3d c = s.poses[i].position();
      INFO("frame " << i);
      REQUIRE(std::abs(c.y() - height) <= 0.0015);  // vibration only
      REQUIRE(std::asin(R(1, 2)) >= -0.003);        // level or pitched down
      REQUIRE(std::asin(R(1, 2)) <= params.driveMaxPitchDownRad + 0.003);
      REQUIRE(std::abs(R(1, 0)) <= 0.003);  // roll
      // The robot's body (0.25 m round, from the floor up to the camera) is clear of everything.
      for (double up = 0.05; up <= params.driveCameraHeightM; up += 0.15)
        REQUIRE(
            scene.objectContaining(Eigen::Vector3f(static_cast<float>(c.x()), static_cast<float>(c.y() + up),
                                                   static_cast<float>(c.z())),
                                   0.25f) < 0);
    }
    double turnPeak = 0.0;
    for (const StressSegment& seg : s.segments) {
      const Peak p = peakOf(s.poses, seg);
      INFO(seg.label << " [" << seg.begin << ", " << seg.end << "): " << p.speedMps << " m/s, " << p.rateDegps
                     << " deg/s");
      if (seg.label == "drive") {
        for (size_t i = seg.begin + 1; i < seg.end; ++i) {
          REQUIRE(speedMps(s.poses, i) >= 1.0);
          REQUIRE(speedMps(s.poses, i) <= 1.5);
        }
        REQUIRE(p.rateDegps < 6.0);  // straight: vibration only (0.002 rad at up to 3.7 Hz)
      } else if (seg.label == "turn") {
        turnPeak = p.rateDegps;
        REQUIRE(p.speedMps < 0.5);
        const Eigen::Vector3d in = s.poses[seg.begin].T_camera_to_world.linear().col(2);
        const Eigen::Vector3d out = s.poses[seg.end - 1].T_camera_to_world.linear().col(2);
        REQUIRE(in.dot(out) < -0.95);  // turned round
      } else {
        REQUIRE(seg.end - seg.begin <= params.driveAccelerateS * kFps + 1);
        REQUIRE(p.rateDegps < 6.0);
      }
    }
    REQUIRE(turnPeak > 30.0);
    REQUIRE(turnPeak < 45.0);
    // Each leg covers the corridor less its end margins: 17 m.
    const double out = (s.poses[s.segments[3].begin].position() - s.poses[0].position()).norm();
    const double back = (s.poses.back().position() - s.poses[s.segments[3].end].position()).norm();
    REQUIRE(out == Approx(17.0).margin(0.01));
    REQUIRE(back == Approx(17.0).margin(0.01));
    if (seed == 0) {
      const ViewStats v = viewStats(scene, s.poses, 0, s.poses.size(), 60);
      INFO("lowest valid fraction " << v.lowestValid);
      REQUIRE(v.lowestValid > 0.5);
    }
  }
  REQUIRE_THROWS_AS(stressTrajectory(StressKind::Drive, generateScene("office", 0), 0), Error);
  REQUIRE_THROWS_AS(stressTrajectory(StressKind::Drive, generateCorridor(0, CorridorParams{4.5}), 0), Error);
}

TEST_CASE("drive: the volume hint holds the whole path, several 5 m volumes long", "[synth][stress][drive]") {
  const Scene scene = generateCorridor(0, CorridorParams{12.0});
  const StressTrajectory s = stressTrajectory(StressKind::Drive, scene, 0);
  VolumeHintParams hintParams;
  hintParams.holdPath = true;
  hintParams.maxSizeM = 256.0;
  const VolumeHints hints =
      estimateVolumeHints(scene, s.poses, iclNuimIntrinsics(), SensorModel{}, hintParams);
  INFO("cube " << hints.sizeM << " m");
  REQUIRE(hints.sizeM > 2 * 5.0);
  const Eigen::Isometry3d T_first_from_world = s.poses.front().T_camera_to_world.inverse();
  for (const TimedPose& p : s.poses) {
    const Eigen::Vector3d c = T_first_from_world * p.position();
    for (int a = 0; a < 3; ++a) {
      const double fraction = hints.initialPosition[a] + c[a] / hints.sizeM;
      REQUIRE(fraction > 0.0);
      REQUIRE(fraction < 1.0);
    }
  }
}
