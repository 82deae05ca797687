// OpenClBackend::pairsInNoise (pipeline/pair_noise.h, issue 55) against the CPU backend's on the same inputs:
// the noisy analytic room of test_opencl_stages.cpp, 160x120, a 128^3 volume, one moved estimate tracked on
// every pyramid level in float and half storage. The OpenCL backend reads its maps back and counts them with
// the CPU backend's countPairsInNoise, so:
//   - with the noise model off its counts are its own track pass's (inliers; too far + bad normals), exactly;
//   - with a Kinect-like noise model its counts are the CPU backend's within the differences of the two
//     backends' maps (float storage: 2 pairs; half: the maps' rounding flips a few more, 0.2% + 2), and they
//     differ from tracking's fixed tests by far more than that (pairs that fail tracking's tests agree within
//     the noise);
//   - like blockSums, it needs a track since the last preprocess or raycast.

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>

#include "pipeline/cpu/cpu_backend.h"
#include "pipeline/opencl/opencl_backend.h"
#include "tests/pipeline/synthetic_room.h"
#include "tests/pipeline/test_opencl_support.h"

using sb::test::kRoomDepthScale;
using sb::test::noisyRoom;

TEST_CASE("OpenCL pairsInNoise counts the CPU backend's pairs within the sensor's noise",
          "[opencl][track][pair_noise]") {
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  sb::PipelineConfig config;
  config.volumeSize = 3.0f;
  config.volumeResolution = 128;
  config.backend = sb::BackendKind::opencl;
  sb::ThreadPool pool(2);
  sb::CpuBackend cpu(config, k, pool);
  sb::OpenClBackend cl(config, k, sb::test::openclTestDevice());
  CHECK(cl.countsPairsInNoise());
  CHECK(cpu.countsPairsInNoise());

  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(1.5, 1.5, 0.9);
  const Eigen::Isometry3f posef = pose.cast<float>();
  const sb::DepthRaw raw = noisyRoom(pose, k);
  const float metresPerUnit = float(1.0 / kRoomDepthScale);
  // A Kinect v1 in its own image (pipeline/pair_noise.h): 0.062 px of disparity noise, 7.5 cm baseline.
  const sb::DepthNoiseModel kinect{0.062, 0.075, k.fx};
  sb::StageTimes cpuTimes, clTimes;
  for (int i = 0; i < 2; ++i) {
    cpu.preprocess(raw, metresPerUnit, 1, cpuTimes);
    cl.preprocess(raw, metresPerUnit, 1, clTimes);
    cpu.integrate(posef, cpuTimes);
    cl.integrate(posef, clTimes);
  }
  // A pass is needed: none since the last preprocess.
  CHECK_THROWS_AS(cl.pairsInNoise(kinect, clTimes), sb::Error);
  const Eigen::Isometry3f estimate =
      (pose * sb::test::motion({0.01, -0.005, 0.008}, 0.8, {0.3, 1.0, -0.2})).cast<float>();

  for (const bool half : {false, true}) {
    cl.setHalfPrecision(half);
    cpu.raycast(posef, 1, cpuTimes);
    cl.raycast(posef, 1, clTimes);
    CHECK_THROWS_AS(cl.pairsInNoise(kinect, clTimes), sb::Error);  // none since the raycast
    cpu.preprocess(raw, metresPerUnit, 1, cpuTimes);
    cl.preprocess(raw, metresPerUnit, 1, clTimes);
    for (int level = 0; level < sb::kPyramidLevels; ++level) {
      INFO((half ? "half storage" : "float storage") << ", level " << level);
      const sb::TrackSums a = cl.track(level, estimate, posef, clTimes);
      const sb::TrackSums b = cpu.track(level, estimate, posef, cpuTimes);

      // Off: tracking's fixed tests on the device's own maps, so its own pass's counts.
      const std::optional<sb::PairCounts> fixed = cl.pairsInNoise(sb::DepthNoiseModel{}, clTimes);
      REQUIRE(fixed);
      INFO("opencl track: " << a[28] << " inliers, " << a[29] + a[30]
                            << " failing; counted off: " << fixed->agreeing << ", " << fixed->failing);
      CHECK(fixed->agreeing == a[28]);
      CHECK(fixed->failing == a[29] + a[30]);

      const std::optional<sb::PairCounts> na = cl.pairsInNoise(kinect, clTimes);
      const std::optional<sb::PairCounts> nb = cpu.pairsInNoise(kinect, cpuTimes);
      REQUIRE(na);
      REQUIRE(nb);
      INFO("within the noise: opencl " << na->agreeing << " agreeing, " << na->failing << " failing; cpu "
                                       << nb->agreeing << ", " << nb->failing << "; cpu track " << b[28]
                                       << ", " << b[29] + b[30]);
      // Float storage: the same maps up to the device's rounding (measured: the same counts at every level).
      // Half storage: the maps rounded to half flip a few pairs (measured: 10 of 16110 at level 0, 2 of 1014
      // at level 2).
      const double pairs = nb->agreeing + nb->failing;
      const double allowed = (half ? 0.002 * pairs : 0.0) + 2;
      CHECK(std::fabs(na->agreeing - nb->agreeing) <= allowed);
      CHECK(std::fabs(na->failing - nb->failing) <= allowed);
      // The widened tests take pairs that tracking's fail, many more than the backends differ by (measured:
      // 1928 of 3381 at level 0, 62 of 246 at level 2).
      CHECK(nb->agreeing - b[28] > 10 * (allowed + 1));
      CHECK(b[29] + b[30] - nb->failing > 10 * (allowed + 1));
      CHECK(na->agreeing - a[28] > 10 * (allowed + 1));
      CHECK(a[29] + a[30] - na->failing > 10 * (allowed + 1));
    }
  }
  CHECK(clTimes[sb::Stage::track] > 0);
}
