// CpuBackend's integrate (the rest of the backend: cpu_backend.cpp): every block of the view with free space
// carved (integrateCarving, KinectFusion's integration, culled by integrate_cull.h), kernels/volume.h's
// integrateVoxel through cpu_integrate.h's rows.
#include <algorithm>
#include <cmath>

#include "kernels/raycast.h"
#include "pipeline/block_distance.h"
#include "pipeline/cpu/cpu_backend.h"
#include "pipeline/cpu/cpu_integrate.h"
#include "pipeline/cpu/stage_timer.h"
#include "pipeline/kernel_args.h"

namespace sb {

namespace {

// The interval of real x where a + b*x >= 0, intersected into [lo, hi].
void clipLinear(double a, double b, double& lo, double& hi) {
  if (b > 0) {
    lo = std::max(lo, -a / b);
  } else if (b < 0) {
    hi = std::min(hi, -a / b);
  } else if (a < 0) {
    hi = lo - 1;  // empty
  }
}

// Or-s into masks[x / 4] the surface mask bits of voxels x in [x0, x1) of one row (int16 (tsdf, weight)
// pairs) whose tsdf is below `below`: `faceBits` for a voxel on its block's lower x face (x % 4 == 0),
// `innerBits` for the others (the row's y and z faces are in both). sbBlockSurfaceMask by rows, kept for speed:
// fused into integrate, it reads rows still in cache (test_cpu_integrate.cpp checks it against the kernel).
// Branch-free, one store per block: a freshly integrated row's tsdf is below the threshold in no pattern.
// Voxel x (logical) is stored at row[2 * (x + delta)] (its physical place in the cyclic buffer; delta 0 for a
// fixed volume).
void orRowSurfaceMask(const int16_t* row, int delta, int x0, int x1, int16_t below, uint8_t innerBits,
                      uint8_t faceBits, uint8_t* masks) {
  static_assert(CpuBackend::kSkipShift == 2, "blocks of 4 voxels along x");
  const auto bitsIf = [](bool set, uint8_t bits) { return static_cast<uint8_t>(-static_cast<int>(set) & bits); };
  const auto tsdf = [&](int x) { return row[2 * (x + delta)]; };
  int x = x0;
  for (; x < x1 && (x & 3) != 0; ++x) masks[x >> 2] |= bitsIf(tsdf(x) < below, innerBits);
  for (; x + 4 <= x1; x += 4) {
    const int16_t* v = row + 2 * (x + delta);
    masks[x >> 2] |= static_cast<uint8_t>(bitsIf(v[0] < below, faceBits) |
                                          bitsIf((v[2] < below) | (v[4] < below) | (v[6] < below), innerBits));
  }
  for (; x < x1; ++x) masks[x >> 2] |= bitsIf(tsdf(x) < below, (x & 3) == 0 ? faceBits : innerBits);
}

}  // namespace

void CpuBackend::integrate(const Eigen::Isometry3f& cameraToWorld, StageTimes& times) {
  StageTimer t(times, Stage::integrate);
  integrateCarving(cameraToWorld);
  times.work.carvingIntegrations += 1;
  times.work.integrateBlocks += static_cast<long long>(cull_.liveCount());
  computeBlockDistance(blockSurfaceMask_, config_.volumeResolution >> kSkipShift, blockDistance_, pool_);
}

void CpuBackend::integrateCarving(const Eigen::Isometry3f& cameraToWorld) {
  const int res = config_.volumeResolution;
  const float voxel = config_.voxelSize();
  // Voxel positions are in the volume frame (the world frame until the volume moves).
  const Eigen::Isometry3f worldToCamera = placement_.toVolumeFrame(cameraToWorld).inverse();
  const SbMat34 w2c = toMat34(worldToCamera.matrix());
  const SbCamera k = toCamera(computeK_);
  const SbVoxelOffset offset = placement_.offset();
  // A logical row of voxels lies in the cyclic buffer as two runs: x < seam at physical x + offset.x, the rest
  // at x + offset.x - R.
  const int seam = res - offset.x;
  const int w = computeK_.width, h = computeK_.height;
  const float maxDepth = depth_.empty() ? 0.0f : *std::max_element(depth_.begin(), depth_.end());
  const double zLimit = maxDepth + config_.mu;  // farther voxels cannot be within the truncation band
  const float3 step = sbRotate(w2c, sbMakeFloat3(voxel, 0.0f, 0.0f));
  const int blocks = res >> kSkipShift;
  const float mu = config_.mu;
  const int maxWeight = config_.maxWeight;
  int16_t* vol = volume_.data();
  const float* depth = depth_.data();
  constexpr int kCullShift = IntegrateCull::kShift;
  cull_.update(pool_, depth, w, h, k, w2c, res, voxel, mu);
  // Empty-space skipping masks (kernels/raycast.h) of the voxels below the raycast's small-step threshold,
  // recomputed for every block whose voxels this integration all visited, or-ed into the old mask for the
  // others (a stale bit there only costs skips).
  const int16_t flagBelow = surfaceTsdfBelow(config_.raycastSmallStepBelow);
  constexpr int kSide = 1 << kSkipShift;
  constexpr int kBlockVoxels = kSide * kSide * kSide;
  uint8_t maskBits[8];
  for (int faces = 0; faces < 8; ++faces) maskBits[faces] = sbSurfaceMaskBits(faces);
  // One chunk per z-slab of blocks, so each block's mask is written by one thread only.
  pool_.parallelFor(0, blocks, 1, [&](int, int bz0, int bz1) {
    std::vector<int> visited(static_cast<size_t>(blocks) * blocks);
    std::vector<uint8_t> mask(static_cast<size_t>(blocks) * blocks);
    for (int bz = bz0; bz < bz1; ++bz) {
      std::fill(visited.begin(), visited.end(), 0);
      std::fill(mask.begin(), mask.end(), 0);
      for (int z = bz * kSide; z < (bz + 1) * kSide; ++z) {
        for (int y = 0; y < res; ++y) {
          const uint8_t* live = cull_.liveRow(y >> kCullShift, z >> kCullShift);
          if (!cull_.anyLive(y >> kCullShift, z >> kCullShift)) continue;
          const float3 base =
              sbTransform(w2c, sbMakeFloat3(0.5f * voxel, (y + 0.5f) * voxel, (z + 0.5f) * voxel));
          // Conservative x-range of the row inside the view frustum and in front of zLimit; the per-voxel
          // checks in integrateVoxel stay exact.
          double lo = 0, hi = res - 1;
          clipLinear(base.z - SB_MIN_PROJECTION_DEPTH, step.z, lo, hi);
          clipLinear(zLimit - base.z, -step.z, lo, hi);
          clipLinear(k.fx * base.x + (k.cx + 0.5) * base.z, k.fx * step.x + (k.cx + 0.5) * step.z, lo, hi);
          clipLinear(-(k.fx * base.x + (k.cx + 0.5 - w) * base.z),
                     -(k.fx * step.x + (k.cx + 0.5 - w) * step.z), lo, hi);
          clipLinear(k.fy * base.y + (k.cy + 0.5) * base.z, k.fy * step.y + (k.cy + 0.5) * step.z, lo, hi);
          clipLinear(-(k.fy * base.y + (k.cy + 0.5 - h) * base.z),
                     -(k.fy * step.y + (k.cy + 0.5 - h) * step.z), lo, hi);
          if (hi < lo) continue;
          const int x0 = std::max(0, static_cast<int>(std::floor(lo)) - 1);
          const int x1 = std::min(res, static_cast<int>(std::ceil(hi)) + 2);
          const size_t rowIndex = static_cast<size_t>(sbWrapVoxel(y, offset.y, res)) * res +
                                  static_cast<size_t>(sbWrapVoxel(z, offset.z, res)) * res * res;
          const size_t blockRow = static_cast<size_t>(y >> kSkipShift) * blocks;
          const int rowFaces = ((y & (kSide - 1)) == 0 ? 2 : 0) + ((z & (kSide - 1)) == 0 ? 4 : 0);
          int16_t* rowVoxels = vol + 2 * rowIndex;
          // Runs of blocks that culling kept, within [x0, x1).
          for (int runStart = x0; runStart < x1;) {
            if (!live[runStart >> kCullShift]) {
              runStart = ((runStart >> kCullShift) + 1) << kCullShift;
              continue;
            }
            int runEnd = runStart;
            while (runEnd < x1 && live[runEnd >> kCullShift]) runEnd = ((runEnd >> kCullShift) + 1) << kCullShift;
            runEnd = std::min(runEnd, x1);
            for (int part = 0; part < 2; ++part) {  // the runs before and after the seam
              const int a = part == 0 ? runStart : std::max(runStart, seam);
              const int b = part == 0 ? std::min(runEnd, seam) : runEnd;
              if (a >= b) continue;
              const int delta = part == 0 ? offset.x : offset.x - res;
              integrateRow(rowVoxels, delta, a, b, base, step, depth, w, h, k, mu, maxWeight);
              orRowSurfaceMask(rowVoxels, delta, a, b, flagBelow, maskBits[rowFaces], maskBits[rowFaces + 1],
                               &mask[blockRow]);
            }
            for (int bx = runStart >> kSkipShift; bx * kSide < runEnd; ++bx)
              visited[blockRow + bx] += std::min(runEnd, (bx + 1) * kSide) - std::max(runStart, bx * kSide);
            runStart = runEnd;
          }
        }
      }
      uint8_t* masks = &blockSurfaceMask_[static_cast<size_t>(bz) * blocks * blocks];
      for (size_t i = 0; i < visited.size(); ++i)
        masks[i] = visited[i] == kBlockVoxels ? mask[i] : (masks[i] | mask[i]);
    }
  });
}

}  // namespace sb
