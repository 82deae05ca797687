// Smooth-surface detection on rendered depth (synth library, Kinect noise model): true for a blank wall,
// false for a furnished view of the living room; the sample count does not depend on the image size.

#include <catch2/catch.hpp>

#include "controller/surface_detector.h"
#include "synth/builtin_trajectory.h"
#include "synth/renderer.h"
#include "synth/scene_generator.h"
#include "synth/synth_sequence.h"

namespace {

sb::DepthRaw renderRaw(const sb::synth::Scene& scene, const Eigen::Isometry3d& pose) {
  const sb::Intrinsics k = sb::synth::iclNuimIntrinsics();
  const sb::synth::Renderer renderer(scene, k);
  sb::DepthMeters meters(k.width, k.height);
  renderer.render(pose, sb::synth::SensorModel{}, 7, meters);
  sb::DepthRaw raw;
  sb::synth::toRaw(meters, sb::synth::kIclDepthScale, raw);
  return raw;
}

}  // namespace

TEST_CASE("a rendered blank wall is a smooth surface, a furnished view is not", "[controller][surface]") {
  const sb::SurfaceParams params;
  sb::synth::Scene wall;
  wall.name = "wall";
  // A wall 1.8 m ahead, turned 20 degrees: the view of a handheld camera close to a blank wall.
  wall.primitives.push_back(sb::synth::makePlane({0.f, 0.f, 1.8f}, {std::sin(0.35f), 0.f, -std::cos(0.35f)}));
  const sb::SurfaceResult flat = detectSmoothSurface(renderRaw(wall, Eigen::Isometry3d::Identity()),
                                                     sb::synth::kIclDepthScale, params);
  INFO("wall stds " << flat.stdM[0] << " " << flat.stdM[1] << " " << flat.stdM[2] << " " << flat.stdM[3]);
  CHECK(flat.smooth);
  CHECK(flat.samplesPerWindow == 32 * 24);  // 640x480, 10% margin, every 8th pixel
  for (int v : flat.valid) CHECK(v > 0.9 * flat.samplesPerWindow);

  const sb::synth::Scene room = sb::synth::generateScene("livingroom", 0);
  const sb::Trajectory trajectory = sb::synth::builtinTrajectory(1);
  const sb::SurfaceResult furnished =
      detectSmoothSurface(renderRaw(room, trajectory[0].T_camera_to_world), sb::synth::kIclDepthScale, params);
  INFO("room stds " << furnished.stdM[0] << " " << furnished.stdM[1] << " " << furnished.stdM[2] << " "
                    << furnished.stdM[3]);
  CHECK_FALSE(furnished.smooth);
}

TEST_CASE("surface detection needs valid samples in every window and a fixed sample grid", "[controller][surface]") {
  const sb::SurfaceParams params;
  sb::DepthRaw holes(640, 480, 2000);
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 320; ++x) holes(x, y) = 0;  // no readings in the top-left quadrant
  CHECK_FALSE(detectSmoothSurface(holes, 1000.0, params).smooth);
  const sb::DepthRaw flat(640, 480, 2000);
  CHECK(detectSmoothSurface(flat, 1000.0, params).smooth);
  sb::DepthRaw step = flat;
  for (int y = 0; y < 480; ++y)
    for (int x = 448; x < 640; ++x) step(x, y) = 3000;  // a 1 m step in the right windows
  const sb::SurfaceResult r = detectSmoothSurface(step, 1000.0, params);
  CHECK_FALSE(r.smooth);
  CHECK(r.stdM[0] < 1e-9);
  CHECK(r.stdM[1] > 0.14);
}
