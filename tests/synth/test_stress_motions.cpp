// The stress kinds added after bursts and blank-wall have their designed numbers: hard-bursts' bursts
// reach 0.06 m/frame and 4 deg/frame; robot drives at a steady 1-1.5 m/s at a fixed height, pitch and roll,
// clear of the furniture; pan sweeps up to 3 deg/frame with the camera in place; corridor's `wall-only`
// frames are exactly those whose exact render is one plane, three stretches of 70-80 frames.

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>

#include "synth/renderer.h"
#include "synth/scene_generator.h"
#include "synth/stress_trajectory.h"
#include "synth/synth_sequence.h"
#include "tests/synth/stress_test_util.h"

using namespace sb;
using namespace sb::synth;
using namespace sb::synth::stress_test;

namespace {

// Largest distance (metres) of a full-size exact render's points from their least-squares plane; infinity
// when a pixel has no reading.
double planeResidualM(const Renderer& renderer, const Eigen::Isometry3d& T_camera_to_world) {
  IdealFrame ideal;
  renderer.renderIdeal(T_camera_to_world, ideal);
  const Intrinsics& k = renderer.intrinsics();
  std::vector<Eigen::Vector3d> points;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int y = 0; y < k.height; ++y)
    for (int x = 0; x < k.width; ++x) {
      const double z = ideal.depthM(x, y);
      if (z <= 0.0) return INFINITY;
      points.emplace_back((x - k.cx) / k.fx * z, (y - k.cy) / k.fy * z, z);
      mean += points.back();
    }
  mean /= static_cast<double>(points.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : points) scatter += (p - mean) * (p - mean).transpose();
  const Eigen::Vector3d normal =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvectors().col(0);
  double worst = 0.0;
  for (const Eigen::Vector3d& p : points) worst = std::max(worst, std::abs(normal.dot(p - mean)));
  return worst;
}

}  // namespace

TEST_CASE("hard-bursts: bursts reach 0.06 m/frame and 4 deg/frame, calm stretches between them",
          "[synth][stress]") {
  for (const std::string& name : sceneNames()) {
    for (uint64_t seed : {0, 1, 2}) {
      const Scene scene = generateScene(name, seed);
      const StressTrajectory s = stressTrajectory(StressKind::HardBursts, scene, seed);
      INFO(name << " seed " << seed << ", " << s.poses.size() << " frames");
      requireStressShape(s, scene);
      int bursts = 0;
      Peak peak;
      for (const StressSegment& seg : s.segments) {
        const Peak p = peakOf(s.poses, seg);
        INFO(seg.label << " [" << seg.begin << ", " << seg.end << "): " << p.speedMps << " m/s, "
                       << p.rateDegps << " deg/s");
        if (seg.label == "burst") {
          ++bursts;
          REQUIRE(p.speedMps > 0.7);
          REQUIRE(p.rateDegps > 45.0);
          peak.speedMps = std::max(peak.speedMps, p.speedMps);
          peak.rateDegps = std::max(peak.rateDegps, p.rateDegps);
        } else {
          REQUIRE(seg.label == "calm");
          requireCalm(p);
        }
      }
      INFO("peaks " << peak.speedMps / kFps << " m/frame, " << peak.rateDegps / kFps << " deg/frame");
      REQUIRE(bursts == 4);
      REQUIRE(peak.speedMps >= 0.06 * kFps);
      REQUIRE(peak.rateDegps >= 4.0 * kFps);
      REQUIRE(peak.speedMps < 0.07 * kFps);
      REQUIRE(peak.rateDegps < 4.5 * kFps);
      if (seed == 0) {
        const ViewStats v = viewStats(scene, s.poses, 0, s.poses.size(), 15);
        INFO("lowest valid fraction " << v.lowestValid << ", lowest ICP constraint " << v.lowestConstraint);
        REQUIRE(v.lowestValid > 0.5);
      }
    }
  }
}

TEST_CASE("robot: a steady 1-1.5 m/s loop at a fixed height, pitch and roll, clear of the furniture",
          "[synth][stress]") {
  const StressParams params;
  for (const std::string& name : sceneNames()) {
    for (uint64_t seed : {0, 1, 2}) {
      const Scene scene = generateScene(name, seed);
      const StressTrajectory s = stressTrajectory(StressKind::Robot, scene, seed);
      INFO(name << " seed " << seed << ", " << s.poses.size() << " frames");
      requireStressShape(s, scene);
      const double height = scene.roomMax.y() - params.robotCameraHeightM;
      for (size_t i = 0; i < s.poses.size(); ++i) {
        const Eigen::Matrix3d R = s.poses[i].T_camera_to_world.linear();
        INFO("frame " << i);
        REQUIRE(std::abs(s.poses[i].position().y() - height) <= 0.0015);  // vibration only
        REQUIRE(std::abs(std::asin(R(1, 2)) - params.robotPitchDownRad) <= 0.003);
        REQUIRE(std::abs(R(1, 0)) <= 0.003);  // roll
      }
      double turnPeak = 0.0;
      for (const StressSegment& seg : s.segments) {
        const Peak p = peakOf(s.poses, seg);
        INFO(seg.label << " [" << seg.begin << ", " << seg.end << "): " << p.speedMps << " m/s, "
                       << p.rateDegps << " deg/s");
        if (seg.label == "drive" || seg.label == "turn") {
          for (size_t i = std::max<size_t>(seg.begin, 1); i < seg.end; ++i) {
            REQUIRE(speedMps(s.poses, i) >= 1.0);
            REQUIRE(speedMps(s.poses, i) <= 1.5);
          }
          if (seg.label == "drive")  // straight: vibration only (the first frame still turns in from an arc)
            REQUIRE(peakOf(s.poses, {seg.label, seg.begin + 1, seg.end}).rateDegps < 6.0);
          if (seg.label == "turn") turnPeak = std::max(turnPeak, p.rateDegps);
        } else {
          REQUIRE((seg.label == "start" || seg.label == "stop"));
          REQUIRE(seg.end - seg.begin <= 31);
        }
      }
      REQUIRE(turnPeak > 45.0);
      REQUIRE(turnPeak < 90.0);
      if (seed == 0) {
        const ViewStats v = viewStats(scene, s.poses, 0, s.poses.size(), 10);
        INFO("lowest valid fraction " << v.lowestValid << ", lowest ICP constraint " << v.lowestConstraint);
        REQUIRE(v.lowestValid > 0.5);
        REQUIRE(v.lowestConstraint > 0.01);
      }
    }
  }
}

TEST_CASE("pan: yaw sweeps up to 3 deg/frame with the camera in place", "[synth][stress]") {
  for (const std::string& name : sceneNames()) {
    for (uint64_t seed : {0, 1, 2}) {
      const Scene scene = generateScene(name, seed);
      const StressTrajectory s = stressTrajectory(StressKind::Pan, scene, seed);
      INFO(name << " seed " << seed << ", " << s.poses.size() << " frames");
      requireStressShape(s, scene);
      Peak peak;
      int sweeps = 0;
      for (const StressSegment& seg : s.segments) {
        const Peak p = peakOf(s.poses, seg);
        INFO(seg.label << " [" << seg.begin << ", " << seg.end << "): " << p.speedMps << " m/s, "
                       << p.rateDegps << " deg/s");
        REQUIRE((seg.label == "pan" || seg.label == "hold"));
        sweeps += seg.label == "pan";
        if (seg.label == "hold") REQUIRE(p.rateDegps < 10.0);
        peak.speedMps = std::max(peak.speedMps, p.speedMps);
        peak.rateDegps = std::max(peak.rateDegps, p.rateDegps);
      }
      for (size_t i = 0; i < s.poses.size(); ++i)
        REQUIRE((s.poses[i].position() - s.poses[0].position()).norm() < 0.05);  // hand sway only
      INFO("peaks " << peak.speedMps / kFps << " m/frame, " << peak.rateDegps / kFps << " deg/frame");
      REQUIRE(sweeps == 5);
      REQUIRE(peak.rateDegps >= 2.9 * kFps);
      REQUIRE(peak.rateDegps <= 3.1 * kFps);
      REQUIRE(peak.speedMps < 0.06);
      if (seed == 0) {
        const ViewStats v = viewStats(scene, s.poses, 0, s.poses.size(), 10);
        INFO("lowest valid fraction " << v.lowestValid << ", lowest ICP constraint " << v.lowestConstraint);
        REQUIRE(v.lowestValid > 0.5);
        REQUIRE(v.lowestConstraint > 0.01);
      }
    }
  }
}

TEST_CASE("corridor: the wall-only frames see exactly one plane, three stretches of 70-80 frames",
          "[synth][stress]") {
  for (const std::string& name : sceneNames()) {
    for (uint64_t seed : {0, 1}) {
      const Scene room = generateScene(name, seed);
      const StressTrajectory s = stressTrajectory(StressKind::Corridor, room, seed);
      const Scene scene = stressScene(StressKind::Corridor, room);
      INFO(name << " seed " << seed << ", " << s.poses.size() << " frames");
      requireStressShape(s, scene);
      const Renderer renderer(scene, iclNuimIntrinsics());
      int wallOnly = 0;
      for (const StressSegment& seg : s.segments) {
        const Peak p = peakOf(s.poses, seg);
        INFO(seg.label << " [" << seg.begin << ", " << seg.end << "): " << p.speedMps << " m/s, "
                       << p.rateDegps << " deg/s");
        REQUIRE(p.speedMps < 1.0);  // the stress is the view, not the motion
        REQUIRE(p.rateDegps < 70.0);
        if (seg.label != "wall-only") {
          const ViewStats v = viewStats(scene, s.poses, seg.begin, seg.end, 5);
          INFO("lowest valid " << v.lowestValid << ", lowest ICP constraint " << v.lowestConstraint);
          REQUIRE(v.lowestValid > 0.5);
          if (seg.label == "furnished") REQUIRE(v.lowestConstraint > 0.005);
          continue;
        }
        ++wallOnly;
        CHECK(seg.end - seg.begin >= 70);
        CHECK(seg.end - seg.begin <= 80);
        // One plane on every frame of it (to float precision), and not on the frames either side of it
        // (where the edge of the image starts to see something else, a sliver at first).
        for (size_t i = seg.begin; i < seg.end; ++i) {
          INFO("frame " << i);
          REQUIRE(planeResidualM(renderer, s.poses[i].T_camera_to_world) < 0.0005);
        }
        REQUIRE(planeResidualM(renderer, s.poses[seg.begin - 1].T_camera_to_world) > 0.001);
        REQUIRE(planeResidualM(renderer, s.poses[seg.end].T_camera_to_world) > 0.001);
      }
      REQUIRE(wallOnly == 3);
    }
  }
}
