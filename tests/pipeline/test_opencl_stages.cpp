// Every stage of the OpenCL backend against the CPU backend (the oracle) on the same inputs: a noisy frame of
// the analytic room with holes, 160x120, a 128^3 volume (small enough for PoCL on 2 cores).
//
// Tolerances, float storage (the differences are exp() and contracted multiply-adds on the device):
//   mm2meters bit-identical; bilateralFilter / halfSampleRobust / depth2vertex within 2e-5 m with identical
//   validity; vertex2normal identical validity, dot >= 0.9999; integrate identical weights except 1e-4 of the
//   voxels, tsdf within 2/32767 (1e-3 of mu where the weights agree); raycast validity differing on <= 0.2% of
//   the pixels, vertices within 1 mm, normals dot >= 0.999; track + reduce inliers within 0.5%, sums within
//   1e-3 (relative), the solved ICP update within 1e-5; render within 1 grey level on >= 99.5% of the pixels.
// Half storage (11-bit mantissa, relative step 4.9e-4): maps within 3e-3 relative except 0.1% of the pixels (+1)
// (threshold tests flipped by rounding), normals from half vertices mean dot >= 0.99; raycast as float but
// vertices within 1e-3 relative and normals dot >= 0.995; the ICP update within 15% (see below).

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>

#include "pipeline/cpu/cpu_backend.h"
#include "pipeline/icp_solve.h"
#include "pipeline/opencl/opencl_backend.h"
#include "tests/pipeline/synthetic_room.h"
#include "tests/pipeline/test_opencl_support.h"

using sb::test::kRoomDepthScale;
using sb::test::noisyRoom;

namespace {

sb::PipelineConfig stageConfig() {
  sb::PipelineConfig c;
  c.volumeSize = 3.0f;
  c.volumeResolution = 128;
  c.backend = sb::BackendKind::opencl;
  return c;
}

Eigen::Isometry3d startPose() {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() = Eigen::Vector3d(1.5, 1.5, 0.9);
  return p;
}

// |a - b| <= relative * |b| + absolute for every value.
size_t countOutside(const std::vector<float>& a, const std::vector<float>& b, double relative, double absolute) {
  size_t bad = 0;
  for (size_t i = 0; i < a.size(); ++i)
    if (!(std::fabs(double(a[i]) - b[i]) <= relative * std::fabs(double(b[i])) + absolute)) ++bad;
  return bad;
}

void checkPreprocess(sb::CpuBackend& cpu, sb::OpenClBackend& cl, bool half) {
  // Half: each stage rounds its output to half (relative step 2^-11 = 4.9e-4), up to 6 roundings on the coarsest
  // level; a rounded input may also flip a threshold test (bilateral range, halfSampleRobust's 0.3 m) on a
  // few pixels: allowed on 0.1% of the pixels (at least 1).
  const double relative = half ? 3e-3 : 0.0;
  const double absolute = half ? 1e-6 : 2e-5;
  const auto outliers = [half](const std::vector<float>& v, size_t perPixel) {
    return half ? perPixel * (v.size() / perPixel / 1000 + 1) : 0;
  };
  CHECK(countOutside(cl.rawMetres(), cpu.rawMetres(), half ? 4.9e-4 : 0.0, 0.0) == 0);
  for (int l = 0; l < sb::kPyramidLevels; ++l) {
    INFO("level " << l << (half ? ", half storage" : ", float"));
    REQUIRE(cl.levelIntrinsics(l).width == cpu.levelIntrinsics(l).width);
    const auto depth = cl.levelDepth(l);
    INFO("depth max difference " << sb::test::maxAbsDifference(depth, cpu.levelDepth(l)));
    CHECK(countOutside(depth, cpu.levelDepth(l), relative, absolute) <= outliers(depth, 1));
    const auto vertices = cl.levelVertices(l);
    CHECK(countOutside(vertices, cpu.levelVertices(l), relative, absolute) <= outliers(vertices, 3));
    const auto normals = sb::test::compareNormals(cl.levelNormals(l), cpu.levelNormals(l));
    INFO("normals: " << normals.validityMismatches << " validity mismatches, min dot " << normals.minDot
                     << ", mean dot " << normals.meanDot << " over " << normals.bothValid);
    CHECK(normals.bothValid > normals.pixels / 2);
    if (half) {
      CHECK(normals.validityMismatches <= normals.pixels / 1000);
      CHECK(normals.meanDot >= 0.99);
    } else {
      CHECK(normals.validityMismatches == 0);
      CHECK(normals.minDot >= 0.9999);
    }
  }
}

}  // namespace

TEST_CASE("OpenCL preprocess matches the CPU backend at csr 1 and 2, float and half storage", "[opencl][preprocess]") {
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  const sb::PipelineConfig config = stageConfig();
  sb::ThreadPool pool(2);
  sb::CpuBackend cpu(config, k, pool);
  sb::OpenClBackend cl(config, k, sb::test::openclTestDevice());
  const sb::DepthRaw raw = noisyRoom(startPose(), k);
  sb::StageTimes cpuTimes, clTimes;
  for (const bool half : {false, true}) {
    cl.setHalfPrecision(half);
    REQUIRE(cl.halfPrecision() == half);
    for (const int csr : {1, 2}) {
      INFO("csr " << csr);
      cpu.preprocess(raw, float(1.0 / kRoomDepthScale), csr, cpuTimes);
      cl.preprocess(raw, float(1.0 / kRoomDepthScale), csr, clTimes);
      checkPreprocess(cpu, cl, half);
    }
  }
  // Every preprocessing stage was timed on the device and on the host.
  for (const sb::Stage s : {sb::Stage::mm2meters, sb::Stage::bilateralFilter, sb::Stage::halfSampleRobust,
                            sb::Stage::depth2vertex, sb::Stage::vertex2normal}) {
    INFO(sb::stageName(s));
    CHECK(clTimes.deviceMs[static_cast<int>(s)] > 0);
    CHECK(clTimes[s] > 0);
  }
}

TEST_CASE("OpenCL integrate, raycast, track, reduce and render match the CPU backend", "[opencl][integrate][raycast][track]") {
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  const sb::PipelineConfig config = stageConfig();
  sb::ThreadPool pool(2);
  sb::CpuBackend cpu(config, k, pool);
  sb::OpenClBackend cl(config, k, sb::test::openclTestDevice());
  const Eigen::Isometry3d pose = startPose();
  const sb::DepthRaw raw = noisyRoom(pose, k);
  sb::StageTimes cpuTimes, clTimes;
  const Eigen::Isometry3f posef = pose.cast<float>();
  for (int i = 0; i < 2; ++i) {  // two integrations: weights 2 and the running average
    cpu.preprocess(raw, float(1.0 / kRoomDepthScale), 1, cpuTimes);
    cl.preprocess(raw, float(1.0 / kRoomDepthScale), 1, clTimes);
    cpu.integrate(posef, cpuTimes);
    cl.integrate(posef, clTimes);
  }

  SECTION("integrate") {
    const size_t voxels = size_t(config.volumeResolution) * config.volumeResolution * config.volumeResolution;
    const int16_t* a = cl.volumeData();
    const int16_t* b = cpu.volumeData();
    size_t weightMismatches = 0, observed = 0;
    int worstTsdf = 0;
    for (size_t v = 0; v < voxels; ++v) {
      if (a[2 * v + 1] != b[2 * v + 1]) {
        ++weightMismatches;
        continue;
      }
      if (b[2 * v + 1] > 0) ++observed;
      worstTsdf = std::max(worstTsdf, std::abs(int(a[2 * v]) - int(b[2 * v])));
    }
    INFO(weightMismatches << " weight mismatches, worst tsdf difference " << worstTsdf << " over " << observed
                          << " observed voxels");
    CHECK(observed > voxels / 20);
    CHECK(weightMismatches <= voxels / 10000);
    CHECK(worstTsdf <= 2);
  }

  SECTION("raycast, track + reduce, render (float and half storage)") {
    for (const bool half : {false, true}) {
      INFO((half ? "half storage" : "float storage"));
      cl.setHalfPrecision(half);
      cpu.raycast(posef, 1, cpuTimes);
      cl.raycast(posef, 1, clTimes);
      const auto vertices = cl.referenceVertices();
      const auto normals = sb::test::compareNormals(cl.referenceNormals(), cpu.referenceNormals());
      INFO("raycast: " << normals.validityMismatches << " validity mismatches, min dot " << normals.minDot
                       << ", vertex max difference " << sb::test::maxAbsDifference(vertices, cpu.referenceVertices()));
      CHECK(normals.bothValid > normals.pixels / 2);
      CHECK(normals.validityMismatches <= normals.pixels / 500);
      CHECK(normals.minDot >= (half ? 0.995 : 0.999));
      CHECK(countOutside(vertices, cpu.referenceVertices(), half ? 1e-3 : 0.0, 1e-3) <= 3 * normals.validityMismatches);

      // A moved estimate against the raycast reference, on every pyramid level.
      cpu.preprocess(raw, float(1.0 / kRoomDepthScale), 1, cpuTimes);
      cl.preprocess(raw, float(1.0 / kRoomDepthScale), 1, clTimes);
      const Eigen::Isometry3f estimate =
          (pose * sb::test::motion({0.01, -0.005, 0.008}, 0.8, {0.3, 1.0, -0.2})).cast<float>();
      for (int level = 0; level < sb::kPyramidLevels; ++level) {
        INFO("level " << level);
        const sb::TrackSums a = cl.track(level, estimate, posef, clTimes);
        const sb::TrackSums b = cpu.track(level, estimate, posef, cpuTimes);
        CHECK(b[28] > 100);
        CHECK(std::fabs(a[28] - b[28]) <= 0.005 * b[28]);
        double scale = 0;
        for (int i = 0; i < 28; ++i) scale = std::fmax(scale, std::fabs(b[i]));
        for (int i = 0; i < 28; ++i) {
          INFO("sum " << i << ": opencl " << a[i] << ", cpu " << b[i]);
          CHECK(std::fabs(a[i] - b[i]) <= (half ? 2e-2 : 1e-3) * scale);
        }
        sb::Twist xa, xb;
        REQUIRE(sb::solveIcpUpdate(a, xa));
        REQUIRE(sb::solveIcpUpdate(b, xb));
        INFO("update difference " << (xa - xb).norm() << ", update " << xb.norm());
        // Half: the maps hold 1 mm steps at 2 m, which moves one ICP update by a few % (up to ~10% on the
        // coarsest level's 40x30 pixels); the runs in test_opencl_run.cpp check where tracking ends up.
        CHECK((xa - xb).norm() <= (half ? 0.15 * xb.norm() : 1e-5));
        // The same pass in blocks of 4 pixels (the tracking quality's structure).
        const sb::TrackSums ba = cl.blockSums(4, clTimes);
        const sb::TrackSums bb = cpu.blockSums(4, cpuTimes);
        CHECK(bb[28] > 10);
        CHECK(std::fabs(ba[28] - bb[28]) <= 0.01 * bb[28] + 1);
        double blockScale = 0;
        for (int i = 7; i < 28; ++i) blockScale = std::fmax(blockScale, std::fabs(bb[i]));
        for (int i = 7; i < 28; ++i) {
          INFO("block sum " << i << ": opencl " << ba[i] << ", cpu " << bb[i]);
          CHECK(std::fabs(ba[i] - bb[i]) <= (half ? 2e-2 : 1e-3) * blockScale);
        }
      }

      const sb::Image<uint8_t> ia = cl.render({1.5f, 1.0f, 0.5f}, clTimes);
      const sb::Image<uint8_t> ib = cpu.render({1.5f, 1.0f, 0.5f}, cpuTimes);
      REQUIRE(ia.size() == ib.size());
      size_t close = 0;
      for (size_t i = 0; i < ia.size(); ++i) close += std::abs(int(ia.data()[i]) - int(ib.data()[i])) <= 1;
      INFO(close << " of " << ia.size() << " pixels within 1 grey level");
      CHECK(close >= ia.size() * 995 / 1000);
    }
    for (const sb::Stage s : {sb::Stage::integrate, sb::Stage::raycast, sb::Stage::track, sb::Stage::reduce,
                              sb::Stage::render}) {
      INFO(sb::stageName(s));
      CHECK(clTimes.deviceMs[static_cast<int>(s)] > 0);
    }
  }
}

TEST_CASE("OpenCL backend: switching to half and back keeps the reference maps (converted on the device)",
          "[opencl][half]") {
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  const sb::PipelineConfig config = stageConfig();
  sb::OpenClBackend cl(config, k, sb::test::openclTestDevice());
  const Eigen::Isometry3f pose = startPose().cast<float>();
  sb::StageTimes times;
  cl.preprocess(noisyRoom(startPose(), k), float(1.0 / kRoomDepthScale), 2, times);
  cl.integrate(pose, times);
  cl.raycast(pose, 2, times);
  const auto floatVertices = cl.referenceVertices();
  cl.setHalfPrecision(true);
  const auto halfVertices = cl.referenceVertices();
  CHECK(countOutside(halfVertices, floatVertices, 1e-3, 1e-6) == 0);
  CHECK(sb::test::maxAbsDifference(halfVertices, floatVertices) > 0);  // really stored as half
  cl.setHalfPrecision(false);
  CHECK(cl.referenceVertices() == halfVertices);  // half -> float is exact
}

TEST_CASE("OpenCL reduce without cl_khr_fp64 (float partial sums with Kahan compensation) matches the double one",
          "[opencl][track]") {
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  const sb::PipelineConfig config = stageConfig();
  sb::opencl::DeviceInfo noFp64 = sb::test::openclTestDevice();
  noFp64.fp64 = false;  // builds the program without SB_HAVE_FP64, as for a device without cl_khr_fp64
  sb::OpenClBackend withDouble(config, k, sb::test::openclTestDevice());
  sb::OpenClBackend withFloat(config, k, noFp64);
  const Eigen::Isometry3d pose = startPose();
  const Eigen::Isometry3f posef = pose.cast<float>();
  const Eigen::Isometry3f estimate = (pose * sb::test::motion({0.01, -0.005, 0.008}, 0.8, {0.3, 1.0, -0.2})).cast<float>();
  sb::StageTimes times;
  for (sb::OpenClBackend* cl : {&withDouble, &withFloat}) {
    cl->preprocess(noisyRoom(pose, k), float(1.0 / kRoomDepthScale), 1, times);
    cl->integrate(posef, times);
    cl->raycast(posef, 1, times);
  }
  const sb::TrackSums a = withFloat.track(0, estimate, posef, times);
  const sb::TrackSums b = withDouble.track(0, estimate, posef, times);
  CHECK(a[28] == b[28]);  // counts are exact in float up to 2^24
  for (size_t i = 0; i < a.size(); ++i) {
    INFO("sum " << i << ": float " << a[i] << ", double " << b[i]);
    CHECK(a[i] == Approx(b[i]).epsilon(1e-6).margin(1e-9));
  }
}
