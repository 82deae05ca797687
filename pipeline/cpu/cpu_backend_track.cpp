// CpuBackend's track + reduce and the tracking quality's block sums (the rest of the backend: cpu_backend.cpp).
#include <algorithm>
#include <chrono>

#include "pipeline/cpu/cpu_backend.h"
#include "core/error.h"
#include "kernels/track.h"
#include "pipeline/cpu/cpu_track.h"
#include "pipeline/kernel_args.h"

namespace sb {

namespace {

// The chunks' partial sums added in chunk order: the same result for any thread count.
TrackSums sumInChunkOrder(const std::vector<TrackSums>& partial) {
  TrackSums total{};
  for (const TrackSums& p : partial)
    for (int i = 0; i < SB_REDUCE_SIZE; ++i) total[i] += p[i];
  return total;
}

}  // namespace

TrackSums CpuBackend::track(int level, const Eigen::Isometry3f& cameraToWorld, const Eigen::Isometry3f& referencePose,
                            StageTimes& times) {
  const Level& in = levels_[level];
  // pipeline/cpu/cpu_track.h: track() and reduce() four pixels at a time. Per chunk of rows, track fills the
  // band (in cache), then reduce sums it into the chunk's partial (double); the partials are summed in chunk
  // order: deterministic for any thread count.
  TrackInputs args;
  args.vertex = in.vertex.data();
  args.normal = in.normal.data();
  args.width = in.k.width;
  args.height = in.k.height;
  args.refVertex = referenceVertex_.data();
  args.refNormal = referenceNormal_.data();
  args.refWidth = referenceK_.width;
  args.refHeight = referenceK_.height;
  args.cameraToWorld = toMat34(cameraToWorld.matrix());
  const Eigen::Matrix<float, 3, 4> projection =
      cameraMatrix(referenceK_) * referencePose.inverse().matrix().topRows<3>();
  args.worldToRefPixel = toMat34(projection);
  args.distanceThreshold = config_.icpDistanceThreshold;
  args.normalThreshold = config_.icpNormalThreshold;
  lastTrack_ = args;
  lastTrackLevel_ = level;
  hasTrack_ = true;
  const int chunks = ThreadPool::chunkCount(0, args.height, kRowsPerChunk);
  std::vector<TrackSums> partial(chunks);
  std::vector<double> trackMs(chunks), reduceMs(chunks);
  const auto start = std::chrono::steady_clock::now();
  pool_.parallelFor(0, args.height, kRowsPerChunk, [&](int chunk, int y0, int y1) {
    thread_local TrackBand band;  // scratch of this thread, kept between calls
    const auto t0 = std::chrono::steady_clock::now();
    trackBand(args, y0, y1, band);
    const auto t1 = std::chrono::steady_clock::now();
    TrackSums& sums = partial[chunk];
    sums.fill(0.0);
    reduceBand(band, sums);
    trackMs[chunk] = std::chrono::duration<double, std::milli>(t1 - t0).count();
    reduceMs[chunk] = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count();
  });
  const TrackSums total = sumInChunkOrder(partial);
  // Wall time of the loop, split between the stages by their share of the per-chunk work.
  double trackSum = 0, reduceSum = 0;
  for (int c = 0; c < chunks; ++c) {
    trackSum += trackMs[c];
    reduceSum += reduceMs[c];
  }
  const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  const double share = trackSum + reduceSum > 0 ? trackSum / (trackSum + reduceSum) : 0.5;
  times[Stage::track] += wall * share;
  times[Stage::reduce] += wall * (1.0 - share);
  return total;
}

TrackSums CpuBackend::blockSums(int block, StageTimes& times) {
  if (!hasTrack_) throw Error("CpuBackend::blockSums called without a track since the last preprocess or raycast");
  if (block < 1) throw Error("CpuBackend::blockSums: block " + std::to_string(block) + " is not positive");
  const auto start = std::chrono::steady_clock::now();
  const TrackInputs& args = lastTrack_;
  const int blocksY = (args.height + block - 1) / block;
  const int perChunk = std::max(1, kRowsPerChunk / block);  // block rows per chunk: bands start on a block
  std::vector<TrackSums> partial(ThreadPool::chunkCount(0, blocksY, perChunk));
  pool_.parallelFor(0, blocksY, perChunk, [&](int chunk, int b0, int b1) {
    thread_local TrackBand band;
    trackBand(args, b0 * block, std::min(b1 * block, args.height), band);
    partial[chunk].fill(0.0);
    reduceBandBlocks(band, args.width, block, partial[chunk]);
  });
  const TrackSums total = sumInChunkOrder(partial);
  // Counted as track: mostly the track pass run again (the block sums are cheap).
  times[Stage::track] += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return total;
}

}  // namespace sb
