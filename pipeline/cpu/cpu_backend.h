#pragma once
// The CPU backend (pipeline/cpu/): runs the stages over images and the volume with a ThreadPool, each with
// the per-pixel math of kernels/. Where the scalar kernel is too slow, a hand-vectorised version over the
// four-lane layer (simd4.h) stays beside it and is bit-identical to it (tests/pipeline/cpu/test_cpu_*.cpp):
// the bilateral filter's interior rows, track + reduce (cpu_track.h), integrate (cpu_integrate.h, with the
// blocks the frame cannot change culled by integrate_cull.h, and the empty-space skipping masks or-ed in row by
// row) and raycast (cpu_raycast.h, skipping empty space by the 4^3 block-distance grid of
// pipeline/block_distance.h, as the OpenCL backend does). Deterministic: work is split into chunks whose
// boundaries do not depend on the thread count, and reductions sum one partial per chunk in chunk order (in
// double), so results are bit-identical for any number of threads.

#include <vector>

#include "core/intrinsics.h"
#include "core/thread_pool.h"
#include "kernels/raycast.h"
#include "pipeline/backend.h"
#include "pipeline/bilateral_taps.h"
#include "pipeline/config.h"
#include "pipeline/cpu/cpu_track.h"
#include "pipeline/integrate_cull.h"
#include "pipeline/ray_bounds.h"
#include "pipeline/volume_placement.h"

namespace sb {

class CpuBackend : public ComputeBackend {
 public:
  static constexpr int kRowsPerChunk = 8;  // image rows per parallel chunk (fixed: determinism)
  // log2 of the side (voxels) of the empty-space skipping blocks (kernels/raycast.h, SB_SKIP_SHIFT).
  static constexpr int kSkipShift = SB_SKIP_SHIFT;

  // `fullSize`: intrinsics of the sensor image. `pool` is borrowed and must outlive the backend.
  CpuBackend(const PipelineConfig& config, const Intrinsics& fullSize, ThreadPool& pool);

  void preprocess(const DepthRaw& raw, float metresPerUnit, int csr, StageTimes& times) override;
  TrackSums track(int level, const Eigen::Isometry3f& cameraToWorld, const Eigen::Isometry3f& referencePose,
                  StageTimes& times) override;
  TrackSums blockSums(int block, StageTimes& times) override;  // runs the last track pass again, in blocks
  std::optional<PairCounts> pairsInNoise(const DepthNoiseModel& model, StageTimes& times) override;
  bool countsPairsInNoise() const override { return true; }
  void integrate(const Eigen::Isometry3f& cameraToWorld, StageTimes& times) override;
  void raycast(const Eigen::Isometry3f& cameraToWorld, int csr, StageTimes& times) override;
  Image<uint8_t> render(const Eigen::Vector3f& lightPosition, StageTimes& times) override;
  const int16_t* volumeData() override { return volume_.data(); }
  void readVolumeBox(const std::array<int, 3>& first, const std::array<int, 3>& extent,
                     int16_t* out) override;
  void moveVolume(const Eigen::Vector3i& cornerVoxels) override;
  void writeVolumeBox(const std::array<int, 3>& first, const std::array<int, 3>& extent,
                      const int16_t* in) override;  // the box's skipping masks anew (sbBlockSurfaceMask)
  const VolumePlacement& placement() const { return placement_; }

  // Host views for tests and tools: 3 floats per pixel (vertex, normal), 1 per pixel (depth), row-major.
  const Intrinsics& levelIntrinsics(int level) const { return levels_[level].k; }
  const std::vector<float>& levelDepth(int level) const { return levels_[level].depth; }
  const std::vector<float>& levelVertices(int level) const { return levels_[level].vertex; }
  const std::vector<float>& levelNormals(int level) const { return levels_[level].normal; }
  const std::vector<float>& rawMetres() const { return depth_; }
  const Intrinsics& referenceIntrinsics() const { return referenceK_; }
  const std::vector<float>& referenceVertices() const { return referenceVertex_; }
  const std::vector<float>& referenceNormals() const { return referenceNormal_; }
  const IntegrateCull& integrateCull() const { return cull_; }  // what the last integrate skipped
  // Empty-space skipping surface masks, one per logical block of (1 << kSkipShift)^3 voxels, x fastest.
  const std::vector<uint8_t>& blockSurfaceMasks() const { return blockSurfaceMask_; }

 private:
  // integrate's voxels (cpu_backend_integrate.cpp): every block in view, free space carved; leaves the skipping
  // masks of the blocks it visits, integrate then updates the block distances.
  void integrateCarving(const Eigen::Isometry3f& cameraToWorld);

  struct Level {
    Intrinsics k;
    std::vector<float> depth, vertex, normal;
  };

  PipelineConfig config_;
  Intrinsics full_;
  ThreadPool& pool_;
  BilateralTaps taps_;  // bilateral spatial taps

  Intrinsics computeK_;          // of the last preprocessed frame
  std::vector<float> depth_;     // mm2meters output (compute size, metres), used by integrate
  std::array<Level, kPyramidLevels> levels_;

  TrackInputs lastTrack_;  // of the last track call, for blockSums
  int lastTrackLevel_ = 0;  // its input level
  bool hasTrack_ = false;  // lastTrack_'s maps are unchanged since (no preprocess or raycast)

  Intrinsics referenceK_;
  std::vector<float> referenceVertex_, referenceNormal_;

  std::vector<int16_t> volume_;            // 2 * R^3: (tsdf, weight) pairs
  // Empty-space skipping (pipeline/block_distance.h), blocks of (1 << kSkipShift)^3 voxels:
  std::vector<uint8_t> blockSurfaceMask_;  // per block: where its voxels below the small-step tsdf lie
  std::vector<uint8_t> blockDistance_;     // per block: Chebyshev distance to a block with surface
  IntegrateCull cull_;                     // integrate's blocks that the current frame cannot change
  RayBounds rayBounds_;                    // the last raycast's ray bounds
  VolumePlacement placement_;              // the moving volume's corner and cyclic offset (fixed: 0)
};

}  // namespace sb
