// The moving volume on the OpenCL backend against the CPU backend (the oracle): the same body on both. A
// volume of the analytic room (160x120, 64^3 of 4 m) moved along x and z (a cyclic buffer: a new address
// offset, kernels/volume.h): on each backend the move is exact, bit for bit (every voxel that stays keeps its
// physical address and content, the planes that left are cleared and nothing else changes), so the two
// backends' volumes differ after it exactly where they differed before it; after one more frame fused (across
// the buffer's wrap) and a raycast from a world pose (interpolating across it), the backends agree within the
// stage tolerances of test_opencl_stages.cpp, which hold without a move too (the backends' integrate is not
// bitwise equal: contracted multiply-adds on the device) (weights identical except 1e-4 of the voxels, tsdf
// within 2/32767; raycast validity differing on <= 0.2% of the pixels, world-frame vertices within 1 mm). A
// box read alone (readVolumeBox, a leaving slab) across the wrap is the volume read through the offset, voxel
// for voxel, on each backend.

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <vector>

#include "pipeline/cpu/cpu_backend.h"
#include "pipeline/opencl/opencl_backend.h"
#include "tests/pipeline/synthetic_room.h"
#include "tests/pipeline/test_opencl_support.h"

namespace {

constexpr int kRes = 64;
constexpr size_t kVoxels = size_t(kRes) * kRes * kRes;

Eigen::Isometry3d at(double x, double y, double z) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, y, z);
  return pose;
}

void fuse(sb::ComputeBackend& backend, const sb::Intrinsics& k, const Eigen::Isometry3d& pose) {
  const sb::DepthFrame frame = sb::test::renderRoom(sb::test::Room{}, pose, k);
  sb::StageTimes times;
  backend.preprocess(frame.depth, float(1.0 / sb::test::kRoomDepthScale), 1, times);
  backend.integrate(pose.cast<float>(), times);
}

// Moves the corner by (+16, 0, -8) voxels ((1, 0, -0.5) m) and counts the voxels that hold what they must.
size_t moveExactly(sb::ComputeBackend& backend) {
  const std::vector<int16_t> before(backend.volumeData(), backend.volumeData() + 2 * kVoxels);
  backend.moveVolume(Eigen::Vector3i(16, 0, -8));
  const int16_t* after = backend.volumeData();
  size_t exact = 0;
  for (int z = 0; z < kRes; ++z)
    for (int y = 0; y < kRes; ++y)
      for (int x = 0; x < kRes; ++x) {
        // Physical voxel (x, y, z): cleared when its x plane left (logical [0, 16) at offset 0) or its z plane
        // left (logical [56, 64)); otherwise untouched.
        const size_t v = size_t(x) + kRes * (size_t(y) + kRes * size_t(z));
        if (x < 16 || z >= 56)
          exact += after[2 * v] == 32767 && after[2 * v + 1] == 0;
        else
          exact += after[2 * v] == before[2 * v] && after[2 * v + 1] == before[2 * v + 1];
      }
  return exact;
}

// After moveExactly (corner (16, 0, -8): offset (16, 0, 56)), ComputeBackend::readVolumeBox of a box across
// the wrap on x and z (4 pieces) against the whole volume read through the offset: the voxels that are exact.
size_t boxReadsExactly(sb::ComputeBackend& backend) {
  const std::array<int, 3> first{40, 5, 0}, extent{20, 20, kRes};  // x from physical 56: 8 planes, then 12
  std::vector<int16_t> box(2 * size_t(extent[0]) * extent[1] * extent[2], -1);
  backend.readVolumeBox(first, extent, box.data());
  const int16_t* volume = backend.volumeData();
  size_t exact = 0, b = 0;
  for (int z = 0; z < extent[2]; ++z)
    for (int y = 0; y < extent[1]; ++y)
      for (int x = 0; x < extent[0]; ++x, ++b) {
        const size_t v = size_t((first[0] + x + 16) % kRes) +
                         kRes * (size_t(first[1] + y) + kRes * size_t((first[2] + z + 56) % kRes));
        exact += box[2 * b] == volume[2 * v] && box[2 * b + 1] == volume[2 * v + 1];
      }
  return exact;
}

}  // namespace

TEST_CASE("OpenCL moving volume: the shift is exact and the backends agree after it", "[opencl][volume_window]") {
  const sb::Intrinsics k = sb::test::roomIntrinsics(160, 120);
  sb::PipelineConfig config;
  config.volumeResolution = kRes;
  config.volumeSize = 4.0f;
  config.backend = sb::BackendKind::opencl;
  sb::ThreadPool pool(2);
  sb::CpuBackend cpu(config, k, pool);
  sb::OpenClBackend cl(config, k, sb::test::openclTestDevice());
  std::vector<int16_t> beforeMove[2];
  int slot = 0;
  for (sb::ComputeBackend* backend : {static_cast<sb::ComputeBackend*>(&cpu), static_cast<sb::ComputeBackend*>(&cl)}) {
    fuse(*backend, k, at(1.5, 1.5, 0.9));
    fuse(*backend, k, at(1.55, 1.5, 0.95));
    beforeMove[slot++].assign(backend->volumeData(), backend->volumeData() + 2 * kVoxels);
    CHECK(moveExactly(*backend) == kVoxels);
    CHECK(boxReadsExactly(*backend) == size_t(20) * 20 * kRes);
  }
  {
    // Bitwise: after the move the backends differ exactly where they differed before it, outside the cleared
    // planes, which are identical.
    const int16_t* a = cl.volumeData();
    const int16_t* c = cpu.volumeData();
    size_t same = 0;
    for (size_t v = 0; v < kVoxels; ++v) {
      const bool differedBefore = std::memcmp(&beforeMove[0][2 * v], &beforeMove[1][2 * v], 4) != 0;
      const bool differNow = std::memcmp(a + 2 * v, c + 2 * v, 4) != 0;
      const size_t x = v % kRes, z = v / (size_t(kRes) * kRes);
      const bool cleared = x < 16 || z >= 56;  // the planes that left (moveExactly)
      same += cleared ? !differNow : differNow == differedBefore;
    }
    CHECK(same == kVoxels);
  }
  for (sb::ComputeBackend* backend : {static_cast<sb::ComputeBackend*>(&cpu), static_cast<sb::ComputeBackend*>(&cl)})
    fuse(*backend, k, at(1.6, 1.45, 1.0));
  const int16_t* a = cl.volumeData();
  const int16_t* b = cpu.volumeData();
  size_t weightMismatches = 0, observed = 0;
  int worstTsdf = 0;
  for (size_t v = 0; v < kVoxels; ++v) {
    if (a[2 * v + 1] != b[2 * v + 1]) {
      ++weightMismatches;
      continue;
    }
    if (b[2 * v + 1] > 0) ++observed;
    worstTsdf = std::max(worstTsdf, std::abs(int(a[2 * v]) - int(b[2 * v])));
  }
  INFO(weightMismatches << " weight mismatches, worst tsdf difference " << worstTsdf << ", " << observed
                        << " observed voxels");
  CHECK(observed > kVoxels / 50);
  CHECK(weightMismatches <= kVoxels / 10000);
  CHECK(worstTsdf <= 2);

  sb::StageTimes times;
  const Eigen::Isometry3f view = at(1.6, 1.45, 1.0).cast<float>();
  cpu.raycast(view, 1, times);
  cl.raycast(view, 1, times);
  const std::vector<float> vertices = cl.referenceVertices();
  const std::vector<float>& expected = cpu.referenceVertices();
  const auto normals = sb::test::compareNormals(cl.referenceNormals(), cpu.referenceNormals());
  size_t far = 0;
  for (size_t i = 0; i < vertices.size(); ++i) far += !(std::fabs(vertices[i] - expected[i]) <= 1e-3);
  INFO("raycast: " << normals.validityMismatches << " validity mismatches, " << far << " vertex values off by > 1 mm");
  CHECK(normals.bothValid > normals.pixels / 2);
  CHECK(normals.validityMismatches <= normals.pixels / 500);
  CHECK(normals.minDot >= 0.999);
  CHECK(far <= 3 * normals.validityMismatches);
}
