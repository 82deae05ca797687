// The procedural rooms: deterministic per (name, seed), varied across seeds, and laid out so that the
// built-in and the ICL-NUIM living-room trajectories stay inside the room, out of the furniture, and see
// mostly surfaces within the sensor range.

#include <catch2/catch.hpp>
#include <filesystem>

#include "core/error.h"
#include "core/trajectory.h"
#include "synth/builtin_trajectory.h"
#include "synth/renderer.h"
#include "synth/scene_generator.h"
#include "synth/stress_views.h"
#include "synth/synth_sequence.h"
#include "tests/support/test_data.h"

using namespace sb;
using namespace sb::synth;

namespace {

constexpr float kClearanceM = 0.15f;  // cameras keep at least this far from walls and furniture

bool samePrimitives(const Scene& a, const Scene& b) {
  if (a.primitives.size() != b.primitives.size()) return false;
  for (size_t i = 0; i < a.primitives.size(); ++i) {
    const Primitive &p = a.primitives[i], &q = b.primitives[i];
    if (p.shape != q.shape || p.center != q.center || p.rotation != q.rotation || p.halfExtents != q.halfExtents)
      return false;
  }
  return true;
}

// Every camera inside the room and outside every object; returns the mean valid-pixel fraction over frames
// rendered every `step` frames (noise on), and the smallest per-frame fraction.
std::pair<double, double> checkTrajectory(const Scene& scene, const Trajectory& trajectory, size_t step) {
  for (size_t i = 0; i < trajectory.size(); ++i) {
    const Eigen::Vector3f p = trajectory[i].position().cast<float>();
    INFO("scene " << scene.name << " seed " << scene.seed << " frame " << i << " at " << p.transpose());
    REQUIRE(scene.insideRoom(p, kClearanceM));
    const int inside = scene.objectContaining(p, kClearanceM);
    INFO("inside " << (inside >= 0 ? scene.primitives[inside].label : ""));
    REQUIRE(inside < 0);
  }
  const Renderer renderer(scene, iclNuimIntrinsics());
  const SensorModel model;
  DepthMeters depth;
  double sum = 0.0, lowest = 1.0;
  size_t frames = 0;
  for (size_t i = 0; i < trajectory.size(); i += step) {
    renderer.render(trajectory[i].T_camera_to_world, model, frameSeed(scene.seed, i), depth);
    size_t valid = 0;
    for (float z : depth.pixels()) valid += z > 0.f;
    const double fraction = static_cast<double>(valid) / depth.size();
    sum += fraction, lowest = std::min(lowest, fraction), ++frames;
  }
  return {sum / frames, lowest};
}

}  // namespace

TEST_CASE("a scene is a function of (name, seed)", "[synth][scene]") {
  for (const std::string& name : sceneNames()) {
    CAPTURE(name);
    const Scene a = generateScene(name, 1);
    REQUIRE(a.primitives.size() > 40);
    REQUIRE(samePrimitives(a, generateScene(name, 1)));
    REQUIRE_FALSE(samePrimitives(a, generateScene(name, 2)));
  }
  REQUIRE_FALSE(samePrimitives(generateScene("livingroom", 1), generateScene("office", 1)));
  REQUIRE_THROWS_AS(generateScene("kitchen", 1), Error);
}

TEST_CASE("scenes hold the furniture their names promise", "[synth][scene]") {
  auto count = [](const Scene& s, const std::string& prefix) {
    int n = 0;
    for (const Primitive& p : s.primitives) n += p.label.rfind(prefix, 0) == 0;
    return n;
  };
  for (uint64_t seed : {0, 1, 2, 3}) {
    CAPTURE(seed);
    const Scene living = generateScene("livingroom", seed);
    REQUIRE(count(living, "column") == 1);
    REQUIRE(count(living, "coffee_table") > 0);
    const Scene office = generateScene("office", seed);
    REQUIRE(count(office, "desk") > 0);
  }
}

TEST_CASE("every wall keeps a stretch of blank wall", "[synth][scene]") {
  constexpr float kStepM = 0.02f, kOffM = 0.03f, kMinBlankM = 1.0f;
  for (const std::string& name : sceneNames()) {
    for (uint64_t seed = 0; seed < 12; ++seed) {
      const Scene scene = generateScene(name, seed);
      const Eigen::Vector3f lo = scene.roomMin, hi = scene.roomMax;
      // Walls as (start, direction, length) just inside the room; a spot is blank when nothing stands in
      // front of it at any height from the floor to the ceiling.
      const std::vector<std::tuple<Eigen::Vector3f, Eigen::Vector3f, float>> walls{
          {{lo.x() + kOffM, 0.f, lo.z()}, Eigen::Vector3f::UnitZ(), hi.z() - lo.z()},
          {{hi.x() - kOffM, 0.f, lo.z()}, Eigen::Vector3f::UnitZ(), hi.z() - lo.z()},
          {{lo.x(), 0.f, lo.z() + kOffM}, Eigen::Vector3f::UnitX(), hi.x() - lo.x()},
          {{lo.x(), 0.f, hi.z() - kOffM}, Eigen::Vector3f::UnitX(), hi.x() - lo.x()}};
      for (const auto& [start, along, length] : walls) {
        float run = 0.f, longest = 0.f;
        for (float s = 0.f; s <= length; s += kStepM) {
          bool blank = true;
          for (float y = lo.y() + 0.05f; y < hi.y() && blank; y += 0.1f) {
            Eigen::Vector3f p = start + s * along;
            p.y() = y;
            blank = scene.objectContaining(p, 0.01f) < 0;
          }
          run = blank ? run + kStepM : 0.f;
          longest = std::max(longest, run);
        }
        INFO(name << " seed " << seed << " wall from " << start.transpose() << ": longest blank " << longest << " m");
        CHECK(longest >= kMinBlankM);
        CHECK(longest < length);  // and the wall is not all blank
      }
    }
  }
}

TEST_CASE("the built-in trajectory stays in the free space and sees the room", "[synth][scene]") {
  const Trajectory trajectory = builtinTrajectory(1200);
  REQUIRE(trajectory.size() == 1200);
  REQUIRE(trajectory[1].timestamp == Approx(1.0 / 30.0));
  // Handheld-like: small steps between frames.
  for (size_t i = 1; i < trajectory.size(); ++i) {
    REQUIRE((trajectory[i].position() - trajectory[i - 1].position()).norm() < 0.01);
  }
  for (const std::string& name : sceneNames()) {
    for (uint64_t seed : {0, 7}) {
      const auto [mean, lowest] = checkTrajectory(generateScene(name, seed), trajectory, 100);
      INFO(name << " seed " << seed << ": mean valid " << mean << ", lowest " << lowest);
      CHECK(mean > 0.6);
      CHECK(lowest > 0.3);
    }
  }
}

TEST_CASE("the ICL-NUIM living-room trajectories fit both scenes", "[synth][scene][data]") {
  const std::string dir = test::sharedDataDir() + "/icl-nuim-trajectories";
  for (int t = 0; t < 4; ++t) {
    const std::string path = dir + "/livingroom" + std::to_string(t) + ".tum";
    REQUIRE(std::filesystem::exists(path));
    const Trajectory trajectory = readTumTrajectory(path);
    REQUIRE(trajectory.size() > 500);
    for (const std::string& name : sceneNames()) {
      for (uint64_t seed : {0, 1}) {
        const auto [mean, lowest] = checkTrajectory(generateScene(name, seed), trajectory, 50);
        INFO(path << " in " << name << " seed " << seed << ": mean valid " << mean << ", lowest " << lowest);
        CHECK(mean > 0.5);
        CHECK(lowest > 0.15);
      }
    }
  }
}

// The seed-0 sequences the benchmark renders: no view along the ICL-NUIM trajectories may leave a motion that
// ICP cannot see. Before the wall fixtures, livingroom traj1 faced a bare wall (smallest constraint 1e-5 ..
// 1e-10, DEFAULT drifted 42 cm) and the office's traj1/traj2 views reached 7e-4 .. 2e-3 (8-13 cm); with them
// the smallest value over every 4th frame of the 8 sequences is 2.4e-3. Seeds other than 0 are not held to
// this (seed 1 still has such views in livingroom traj1 and office traj1).
TEST_CASE("seed 0: every view along the ICL-NUIM trajectories constrains every ICP motion",
          "[synth][scene][data]") {
  constexpr double kMinConstraint = 1e-3;  // measureView's smallest eigenvalue
  constexpr size_t kStep = 8;              // frames
  const std::string dir = test::sharedDataDir() + "/icl-nuim-trajectories";
  for (const std::string& name : sceneNames()) {
    const Scene scene = generateScene(name, 0);
    const Renderer renderer(scene, iclNuimIntrinsics());
    for (int t = 0; t < 4; ++t) {
      const std::string path = dir + "/livingroom" + std::to_string(t) + ".tum";
      REQUIRE(std::filesystem::exists(path));
      const Trajectory trajectory = readTumTrajectory(path);
      double lowest = 1e9;
      size_t lowestFrame = 0;
      for (size_t i = 0; i < trajectory.size(); i += kStep) {
        const double c = measureView(renderer, trajectory[i].T_camera_to_world).minConstraint;
        if (c < lowest) lowest = c, lowestFrame = i;
      }
      INFO(name << " along " << path << ": smallest constraint " << lowest << " at frame " << lowestFrame);
      CHECK(lowest > kMinConstraint);
    }
  }
}
