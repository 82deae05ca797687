#include "pipeline/cpu/cpu_backend.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>

#include "core/error.h"
#include "kernels/preprocess.h"
#include "kernels/raycast.h"
#include "kernels/track.h"
#include "pipeline/block_distance.h"
#include "pipeline/cpu/cpu_raycast.h"
#include "pipeline/cpu/cpu_track.h"
#include "pipeline/cpu/simd4.h"
#include "pipeline/cpu/stage_timer.h"
#include "pipeline/kernel_args.h"

namespace sb {

namespace {

constexpr int kTile = 8;          // raycast tile side, pixels

// Runs fn(x, y) over a width x height image, rows split in fixed chunks.
template <typename Fn>
void forEachPixel(ThreadPool& pool, int width, int height, const Fn& fn) {
  pool.parallelFor(0, height, CpuBackend::kRowsPerChunk, [&](int, int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < width; ++x) fn(x, y);
  });
}

// The interior pixels x in [r, w - r) of row y (rows y - r .. y + r exist) of bilateralFilter, tap by tap (a
// vectorisable loop over x) with the kernel's bilateralWeight and the kernel's summation order, so the result
// is bit-identical to bilateralFilter() (tests/pipeline/test_kernels.cpp checks it). It stays beside the
// kernel for speed: GCC vectorises this loop over x, not the kernel's per-pixel taps. ws, vs: w floats of
// scratch.
SB_SIMD_CLONES void bilateralInteriorRow(float* out, const float* in, int w, int y, const float* g, int r,
                                         float rangeFactor, float* ws, float* vs) {
  std::fill(ws, ws + w, 0.0f);
  std::fill(vs, vs + w, 0.0f);
  const float* centre = in + static_cast<size_t>(y) * w;
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      const float spatial = g[dx + r] * g[dy + r];
      const float* tap = in + static_cast<size_t>(y + dy) * w + dx;
      for (int x = r; x < w - r; ++x) {
        const float v = tap[x];
        const float weight = bilateralWeight(v, centre[x], spatial, rangeFactor);
        ws[x] += weight;
        vs[x] += weight * v;
      }
    }
  }
  float* row = out + static_cast<size_t>(y) * w;
  for (int x = r; x < w - r; ++x) row[x] = centre[x] > 0.0f ? vs[x] / ws[x] : 0.0f;
}

}  // namespace

CpuBackend::CpuBackend(const PipelineConfig& config, const Intrinsics& fullSize, ThreadPool& pool)
    : config_(config), full_(fullSize), pool_(pool), placement_(config.volumeResolution, config.voxelSize()) {
  validateConfig(config_);
  taps_ = bilateralTaps(config_);
  const size_t voxels = static_cast<size_t>(config_.volumeResolution) * config_.volumeResolution * config_.volumeResolution;
  volume_.resize(2 * voxels);
  for (size_t i = 0; i < voxels; ++i) {
    volume_[2 * i] = static_cast<int16_t>(SB_TSDF_SCALE);
    volume_[2 * i + 1] = 0;
  }
  const int blocks = config_.volumeResolution >> kSkipShift;
  blockSurfaceMask_.assign(static_cast<size_t>(blocks) * blocks * blocks, 0);
  computeBlockDistance(blockSurfaceMask_, blocks, blockDistance_, pool_);
}

void CpuBackend::preprocess(const DepthRaw& raw, float metresPerUnit, int csr, StageTimes& times) {
  computeK_ = full_.scaled(csr);
  hasTrack_ = false;
  const int w = computeK_.width, h = computeK_.height;
  const size_t n = static_cast<size_t>(w) * h;
  depth_.resize(n);
  {
    StageTimer t(times, Stage::mm2meters);
    const uint16_t* in = raw.data();
    const int inWidth = raw.width();
    float* out = depth_.data();
    forEachPixel(pool_, w, h, [&](int x, int y) { mm2meters(out, w, in, inWidth, csr, metresPerUnit, x, y); });
  }
  for (int l = 0; l < kPyramidLevels; ++l) {
    Level& level = levels_[l];
    level.k = full_.scaled(csr << l);
    const size_t ln = static_cast<size_t>(level.k.width) * level.k.height;
    level.depth.resize(ln);
    level.vertex.resize(3 * ln);
    level.normal.resize(3 * ln);
  }
  {
    StageTimer t(times, Stage::bilateralFilter);
    const float* in = depth_.data();
    float* out = levels_[0].depth.data();
    const float* g = taps_.weights.data();
    const int r = taps_.radius;
    const float sigma = config_.bilateralRangeSigma;
    const float rangeFactor = -1.0f / (2.0f * sigma * sigma);
    // Interior pixels of a row by bilateralInteriorRow (bit-identical to bilateralFilter()); the border
    // (clamped taps) runs the per-pixel kernel.
    pool_.parallelFor(0, h, kRowsPerChunk, [&](int, int y0, int y1) {
      std::vector<float> weightSum(w), valueSum(w);
      for (int y = y0; y < y1; ++y) {
        if (y < r || y >= h - r || w <= 2 * r) {
          for (int x = 0; x < w; ++x) bilateralFilter(out, in, w, h, g, r, sigma, x, y);
          continue;
        }
        for (int x = 0; x < r; ++x) bilateralFilter(out, in, w, h, g, r, sigma, x, y);
        for (int x = w - r; x < w; ++x) bilateralFilter(out, in, w, h, g, r, sigma, x, y);
        bilateralInteriorRow(out, in, w, y, g, r, rangeFactor, weightSum.data(), valueSum.data());
      }
    });
  }
  {
    StageTimer t(times, Stage::halfSampleRobust);
    for (int l = 1; l < kPyramidLevels; ++l) {
      const Level& fine = levels_[l - 1];
      Level& coarse = levels_[l];
      const float* in = fine.depth.data();
      float* out = coarse.depth.data();
      const int cw = coarse.k.width, fw = fine.k.width, fh = fine.k.height;
      const float maxDiff = config_.halfSampleMaxDifference;
      forEachPixel(pool_, cw, coarse.k.height,
                   [&](int x, int y) { halfSampleRobust(out, cw, in, fw, fh, maxDiff, x, y); });
    }
  }
  {
    StageTimer t(times, Stage::depth2vertex);
    for (Level& level : levels_) {
      const SbCamera k = toCamera(level.k);
      float* out = level.vertex.data();
      const float* in = level.depth.data();
      const int lw = level.k.width;
      forEachPixel(pool_, lw, level.k.height, [&](int x, int y) { depth2vertex(out, in, lw, k, x, y); });
    }
  }
  {
    StageTimer t(times, Stage::vertex2normal);
    for (Level& level : levels_) {
      float* out = level.normal.data();
      const float* in = level.vertex.data();
      const int lw = level.k.width, lh = level.k.height;
      forEachPixel(pool_, lw, lh, [&](int x, int y) { vertex2normal(out, in, lw, lh, x, y); });
    }
  }
}

void CpuBackend::raycast(const Eigen::Isometry3f& cameraToWorld, int csr, StageTimes& times) {
  StageTimer t(times, Stage::raycast);
  referenceK_ = full_.scaled(csr);
  hasTrack_ = false;
  const int w = referenceK_.width, h = referenceK_.height;
  referenceVertex_.resize(3 * static_cast<size_t>(w) * h);
  referenceNormal_.resize(3 * static_cast<size_t>(w) * h);
  RaycastInputs in;
  in.volume = volume_.data();
  in.resolution = config_.volumeResolution;
  in.offset = placement_.offset();
  in.size = config_.volumeSize;
  in.blockDistance = config_.emptySpaceSkipping ? blockDistance_.data() : nullptr;
  in.distanceShift = kSkipShift;
  in.cameraToWorld = toMat34(placement_.toVolumeFrame(cameraToWorld).matrix());
  in.camera = toCamera(referenceK_);
  if (config_.emptySpaceSkipping) {  // the ray bounds come from the same grid
    rayBounds_.compute(blockDistance_.data(), kSkipShift, config_.volumeResolution, config_.volumeSize,
                       in.cameraToWorld, in.camera, w, h);
    in.rayBounds = rayBounds_.bounds().data();
    in.boundsColumns = rayBounds_.columns();
  }
  in.nearPlane = config_.nearPlane;
  in.farPlane = config_.farPlane;
  in.largeStep = config_.raycastLargeStep * config_.mu;
  in.smallStep = config_.raycastSmallStep * config_.voxelSize();
  in.smallStepBelow = config_.raycastSmallStepBelow;
  float* outV = referenceVertex_.data();
  float* outN = referenceNormal_.data();
  // Square tiles: neighbouring rays read neighbouring voxels.
  std::atomic<long long> samples{0}, lookups{0};
  pool_.parallelFor(0, h, kTile, [&](int, int y0, int y1) {
    RaycastWork chunk;
    for (int tx = 0; tx < w; tx += kTile) {
      const RaycastWork rect = raycastRect(in, outV, outN, w, tx, std::min(w, tx + kTile), y0, y1);
      chunk.samples += rect.samples;
      chunk.lookups += rect.lookups;
    }
    samples += chunk.samples;
    lookups += chunk.lookups;
  });
  times.work.raycastPixels = static_cast<long long>(w) * h;
  times.work.raycastSamples = samples.load();
  times.work.raycastLookups = lookups.load();
  if (placement_.moved()) {  // the maps in the world frame (a volume that never moved skips this)
    const Eigen::Vector3f c = placement_.cornerMetres();
    const float3 corner = sbMakeFloat3(c.x(), c.y(), c.z());
    forEachPixel(pool_, w, h, [&](int x, int y) { offsetVertex(outV, outN, corner, y * w + x); });
  }
}

void CpuBackend::readVolumeBox(const std::array<int, 3>& first, const std::array<int, 3>& extent,
                               int16_t* out) {
  const size_t res = size_t(config_.volumeResolution);
  const size_t rowOut = size_t(extent[0]), planeOut = rowOut * size_t(extent[1]);
  for (const BoxPiece& p : boxPieces(first, extent, placement_.offset(), config_.volumeResolution))
    pool_.parallelFor(0, p.extent[2], 8, [&](int, int z0, int z1) {
      for (int z = z0; z < z1; ++z)
        for (int y = 0; y < p.extent[1]; ++y) {  // one run of x: contiguous in both
          const size_t from =
              size_t(p.physical[0]) + res * (size_t(p.physical[1] + y) + res * size_t(p.physical[2] + z));
          const size_t to =
              size_t(p.inBox[0]) + rowOut * size_t(p.inBox[1] + y) + planeOut * size_t(p.inBox[2] + z);
          std::memcpy(out + 2 * to, volume_.data() + 2 * from, 2 * sizeof(int16_t) * size_t(p.extent[0]));
        }
    });
}

void CpuBackend::writeVolumeBox(const std::array<int, 3>& first, const std::array<int, 3>& extent,
                                const int16_t* in) {
  const int res = config_.volumeResolution;
  const size_t rowIn = size_t(extent[0]), planeIn = rowIn * size_t(extent[1]);
  for (const BoxPiece& p : boxPieces(first, extent, placement_.offset(), res))
    pool_.parallelFor(0, p.extent[2], 8, [&](int, int z0, int z1) {
      for (int z = z0; z < z1; ++z)
        for (int y = 0; y < p.extent[1]; ++y) {
          const size_t to = size_t(p.physical[0]) +
                            size_t(res) * (size_t(p.physical[1] + y) + size_t(res) * size_t(p.physical[2] + z));
          const size_t from = size_t(p.inBox[0]) + rowIn * size_t(p.inBox[1] + y) + planeIn * size_t(p.inBox[2] + z);
          std::memcpy(volume_.data() + 2 * to, in + 2 * from, 2 * sizeof(int16_t) * size_t(p.extent[0]));
        }
    });
  // The skipping masks of every block the box touches (and of the blocks below it: a mask holds the first
  // voxel layer of its upper neighbours), from the volume as it is now.
  const int blocks = res >> kSkipShift;
  const int16_t below = surfaceTsdfBelow(config_.raycastSmallStepBelow);
  const SbVoxelOffset o = placement_.offset();
  std::array<int, 3> lo{}, hi{};
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(0, (first[a] >> kSkipShift) - 1);
    hi[a] = std::min(blocks, ((first[a] + extent[a] - 1) >> kSkipShift) + 1);
  }
  pool_.parallelFor(lo[2], hi[2], 1, [&](int, int z0, int z1) {
    for (int bz = z0; bz < z1; ++bz)
      for (int by = lo[1]; by < hi[1]; ++by)
        for (int bx = lo[0]; bx < hi[0]; ++bx)
          blockSurfaceMask_[size_t(bx) + size_t(blocks) * (size_t(by) + size_t(blocks) * size_t(bz))] =
              sbBlockSurfaceMask(volume_.data(), res, o, kSkipShift, below, bx, by, bz);
  });
  computeBlockDistance(blockSurfaceMask_, blocks, blockDistance_, pool_);
}

void CpuBackend::moveVolume(const Eigen::Vector3i& cornerVoxels) {
  const Eigen::Vector3i before = placement_.corner();
  const int res = config_.volumeResolution;
  int16_t* vol = volume_.data();
  for (const VolumePlacement::Clear& c : placement_.moveTo(cornerVoxels)) {
    // kernels/volume.h's clearSlab, rows of x innermost.
    pool_.parallelFor(0, res, 8, [&](int, int w0, int w1) {
      for (int w = w0; w < w1; ++w) {
        if (c.axis == 0) {
          for (int v = 0; v < res; ++v)
            for (int u = 0; u < c.count; ++u) clearSlab(vol, res, c.axis, c.first, u, v, w);
        } else {
          for (int u = 0; u < c.count; ++u)
            for (int v = 0; v < res; ++v) clearSlab(vol, res, c.axis, c.first, u, v, w);
        }
      }
    });
    // The skipping grid is kept in logical blocks: it moves with the volume, the blocks that came in are empty.
    const int moved = cornerVoxels[c.axis] - before[c.axis];
    shiftGrid(blockSurfaceMask_.data(), res >> kSkipShift, c.axis, moved / (1 << kSkipShift), 0, pool_);
  }
  computeBlockDistance(blockSurfaceMask_, res >> kSkipShift, blockDistance_, pool_);
}

Image<uint8_t> CpuBackend::render(const Eigen::Vector3f& lightPosition, StageTimes& times) {
  StageTimer t(times, Stage::render);
  const int w = referenceK_.width, h = referenceK_.height;
  Image<uint8_t> image(w, h);
  uint8_t* out = image.data();
  const float3 light = sbMakeFloat3(lightPosition.x(), lightPosition.y(), lightPosition.z());
  const float ambient = config_.renderAmbient;
  const float* v = referenceVertex_.data();
  const float* n = referenceNormal_.data();
  forEachPixel(pool_, w, h, [&](int x, int y) { ::render(out, v, n, w, light, ambient, x, y); });
  return image;
}

}  // namespace sb
