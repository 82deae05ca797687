// A rendered sequence re-reads through sb::openSequence with the same pixels, timestamps and groundtruth.

#include <catch2/catch.hpp>
#include <filesystem>

#include "core/error.h"
#include "drivers/sequence.h"
#include "synth/builtin_trajectory.h"
#include "synth/renderer.h"
#include "synth/scene_generator.h"
#include "synth/synth_sequence.h"
#include "tests/support/test_data.h"

using namespace sb;
using namespace sb::synth;

TEST_CASE("a synthetic sequence round-trips through openSequence", "[synth][sequence]") {
  const std::string dir = test::scratchDir("synth_roundtrip");
  SynthOptions options;
  options.outDir = dir;
  options.overwrite = true;  // scratchDir already created it
  options.scene = "office";
  options.seed = 4;
  options.intrinsics = iclNuimIntrinsics().scaled(4);  // 160x120 keeps the test fast
  options.maxFrames = 10;
  const Trajectory trajectory = builtinTrajectory(25);
  size_t lastProgress = 0;
  const SynthResult result = synthesizeSequence(trajectory, options, [&](size_t done, size_t total) {
    REQUIRE(done > lastProgress);
    REQUIRE(total == 10);
    lastProgress = done;
  });
  REQUIRE(result.frames == 10);
  REQUIRE(lastProgress == 10);
  REQUIRE(result.validFraction > 0.3);
  REQUIRE(result.volume.sizeM >= 4.0);
  REQUIRE(result.volume.sizeM <= 8.0);

  auto source = openSequence(dir);
  const SequenceInfo& info = source->info();
  REQUIRE(info.frameCount == 10);
  REQUIRE(info.depthScale == 5000.0);
  REQUIRE(info.intrinsics.width == 160);
  REQUIRE(info.intrinsics.fx == Approx(481.2f / 4));
  REQUIRE(info.volumeSize.has_value());
  REQUIRE(*info.volumeSize == Approx(result.volume.sizeM));
  REQUIRE(info.volumeInitialPosition.has_value());
  for (int a = 0; a < 3; ++a) REQUIRE((*info.volumeInitialPosition)[a] == Approx(result.volume.initialPosition[a]));

  const Trajectory groundTruth = readTumTrajectory(info.groundTruthPath);
  REQUIRE(groundTruth.size() == 10);
  const Scene scene = generateScene("office", 4);
  const Renderer renderer(scene, options.intrinsics);
  DepthMeters meters;
  DepthRaw expected;
  for (size_t i = 0; i < 10; ++i) {
    CAPTURE(i);
    REQUIRE(groundTruth[i].timestamp == Approx(trajectory[i].timestamp).margin(1e-6));
    REQUIRE((groundTruth[i].position() - trajectory[i].position()).norm() < 1e-6);
    REQUIRE(groundTruth[i].T_camera_to_world.linear().isApprox(trajectory[i].T_camera_to_world.linear(), 1e-6));
    const auto frame = source->next();
    REQUIRE(frame.has_value());
    REQUIRE(frame->timestamp == Approx(trajectory[i].timestamp).margin(1e-6));
    renderer.render(trajectory[i].T_camera_to_world, options.sensor, frameSeed(4, i), meters);
    toRaw(meters, 5000.0, expected);
    REQUIRE(frame->depth.pixels() == expected.pixels());
  }
  REQUIRE_FALSE(source->next().has_value());
}

TEST_CASE("synthesizeSequence reports bad input", "[synth][sequence]") {
  SynthOptions options;
  options.outDir = test::scratchDir("synth_errors");
  options.overwrite = true;
  REQUIRE_THROWS_AS(synthesizeSequence({}, options), Error);
  Trajectory outside = builtinTrajectory(2);
  outside[1].T_camera_to_world.translation().x() = 10.0;
  REQUIRE_THROWS_WITH(synthesizeSequence(outside, options), Catch::Contains("outside"));
  options.scene = "garage";
  REQUIRE_THROWS_WITH(synthesizeSequence(builtinTrajectory(2), options), Catch::Contains("livingroom, office"));
}
