// Empty-space skipping must not change what the raycast finds: the CPU backend with skipping on and off, on
// the same integrated volume, seen from the integration pose and from moved poses (rays that pass near edges,
// graze surfaces, cross thin objects and enter the unobserved space behind surfaces).

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>

#include "kernels/common.h"
#include "pipeline/cpu/cpu_backend.h"
#include "tests/pipeline/synthetic_room.h"

using sb::test::kRoomDepthScale;

namespace {

struct SkipDifference {
  size_t pixels = 0, bothValid = 0, validityMismatches = 0, farVertices = 0;
  double minDot = 1.0;
};

SkipDifference compare(const sb::CpuBackend& a, const sb::CpuBackend& b, double vertexTolerance) {
  SkipDifference d;
  const auto &va = a.referenceVertices(), &vb = b.referenceVertices();
  const auto &na = a.referenceNormals(), &nb = b.referenceNormals();
  d.pixels = na.size() / 3;
  for (size_t i = 0; i < d.pixels; ++i) {
    const bool okA = na[3 * i] != SB_INVALID_NORMAL, okB = nb[3 * i] != SB_INVALID_NORMAL;
    if (okA != okB) ++d.validityMismatches;
    if (!okA || !okB) continue;
    ++d.bothValid;
    double dot = 0, dist2 = 0;
    for (int c = 0; c < 3; ++c) {
      dot += double(na[3 * i + c]) * nb[3 * i + c];
      dist2 += (double(va[3 * i + c]) - vb[3 * i + c]) * (double(va[3 * i + c]) - vb[3 * i + c]);
    }
    d.minDot = std::fmin(d.minDot, dot);
    if (std::sqrt(dist2) > vertexTolerance) ++d.farVertices;
  }
  return d;
}

}  // namespace

TEST_CASE("raycast finds the same surface with and without empty-space skipping", "[pipeline][raycast]") {
  // The room, and the room whose box is a 1 cm plate (under half a voxel: its two sides' truncation bands
  // overlap), integrated from two views on opposite sides of the box.
  sb::test::Room thin;
  thin.boxMax.z() = thin.boxMin.z() + 0.01;
  const sb::test::Room room = GENERATE_COPY(sb::test::Room{}, thin);
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  sb::PipelineConfig config;
  config.volumeSize = 3.0f;
  config.volumeResolution = 128;
  sb::ThreadPool pool(2);
  sb::CpuBackend skipping(config, k, pool);
  config.emptySpaceSkipping = false;
  sb::CpuBackend plain(config, k, pool);
  Eigen::Isometry3d front = Eigen::Isometry3d::Identity();
  front.translation() = Eigen::Vector3d(1.5, 1.5, 0.9);
  Eigen::Isometry3d behind = Eigen::Isometry3d::Identity();  // beside the box, looking back at it
  behind.translation() = Eigen::Vector3d(1.9, 1.6, 2.6);
  behind.linear() = Eigen::AngleAxisd(-M_PI * 0.7, Eigen::Vector3d::UnitY()).toRotationMatrix();
  sb::StageTimes times;
  for (const Eigen::Isometry3d& view : {front, front, behind}) {
    const sb::DepthRaw raw = sb::test::renderRoom(room, view, k).depth;
    for (sb::CpuBackend* b : {&skipping, &plain}) {
      b->preprocess(raw, float(1.0 / kRoomDepthScale), 1, times);
      b->integrate(view.cast<float>(), times);
    }
  }
  for (const Eigen::Vector3d& offset : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.15, -0.1, 0.2),
                                        Eigen::Vector3d(-0.3, 0.2, 0.5), Eigen::Vector3d(0.4, 0.3, -0.2)}) {
    for (const double yawDegrees : {0.0, 25.0, -40.0}) {
      Eigen::Isometry3d pose = front;
      pose.translation() += offset;
      pose.linear() =
          Eigen::AngleAxisd(yawDegrees * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
      skipping.raycast(pose.cast<float>(), 1, times);
      plain.raycast(pose.cast<float>(), 1, times);
      // Skipping leaves out only samples that cannot end the march or change its step: the same maps.
      const SkipDifference d = compare(skipping, plain, 0.0);
      INFO("box thickness " << room.boxMax.z() - room.boxMin.z() << " m, offset " << offset.transpose()
                            << ", yaw " << yawDegrees << ": " << d.validityMismatches
                            << " validity mismatches, min dot " << d.minDot << ", " << d.farVertices << " of "
                            << d.bothValid << " vertices differ");
      CHECK(d.bothValid > d.pixels / 5);
      CHECK(d.validityMismatches == 0);
      CHECK(d.minDot >= 0.999999);
      CHECK(d.farVertices == 0);
    }
  }
}
