#pragma once
// The OpenCL backend: the kernels/ functions through the kernels/cl/ wrappers on one OpenCL device (PoCL in
// tests and CI, Mali on the board, any OpenCL 1.2 GPU). Every stage runs on the device, the ICP reduction
// included (only the SB_REDUCE_SIZE sums are read back); only the empty-space skipping distances are computed
// on the host, as the CPU backend does, from the block masks read back after integrate (2 x 262 KB per
// integration at 256^3, pipeline/block_distance.h). Buffers are allocated once for the full sensor size,
// so csr changes reuse them; the raw frame goes through a host-allocated buffer that is mapped and filled
// (zero-copy on unified-memory devices such as Mali). Kernel times come from profiling events
// (StageTimes::deviceMs). The OpenCL types stay inside the .cpp files.

#include <memory>
#include <vector>

#include "core/intrinsics.h"
#include "pipeline/backend.h"
#include "pipeline/config.h"
#include "pipeline/opencl/device.h"

namespace sb {

class OpenClBackend : public ComputeBackend {
 public:
  // `fullSize`: intrinsics of the sensor image. Builds the float program (and the half one when
  // config.openclHalfStorage). Throws sb::Error naming the device and the OpenCL failure.
  OpenClBackend(const PipelineConfig& config, const Intrinsics& fullSize, const opencl::DeviceInfo& device);
  ~OpenClBackend() override;

  void preprocess(const DepthRaw& raw, float metresPerUnit, int csr, StageTimes& times) override;
  TrackSums track(int level, const Eigen::Isometry3f& cameraToWorld, const Eigen::Isometry3f& referencePose,
                  StageTimes& times) override;
  TrackSums blockSums(int block, StageTimes& times) override;
  // The last track's maps read back (as float) and counted on the host by the CPU backend's countPairsInNoise
  // (opencl_pair_noise.cpp): one definition of the widened tests; once per view a relocaliser checks.
  std::optional<PairCounts> pairsInNoise(const DepthNoiseModel& model, StageTimes& times) override;
  bool countsPairsInNoise() const override { return true; }
  void integrate(const Eigen::Isometry3f& cameraToWorld, StageTimes& times) override;
  void raycast(const Eigen::Isometry3f& cameraToWorld, int csr, StageTimes& times) override;
  Image<uint8_t> render(const Eigen::Vector3f& lightPosition, StageTimes& times) override;
  const int16_t* volumeData() override;
  // The box alone: one rectangular read per piece of it (clEnqueueReadBufferRect), not the whole volume.
  void readVolumeBox(const std::array<int, 3>& first, const std::array<int, 3>& extent,
                     int16_t* out) override;
  void moveVolume(const Eigen::Vector3i& cornerVoxels) override;  // clearSlabKernel, the skipping grid anew
  void writeVolumeBox(const std::array<int, 3>& first, const std::array<int, 3>& extent,
                      const int16_t* in) override;  // clEnqueueWriteBufferRect per piece, the skipping grid anew

  // Half storage through vload_half / vstore_half is core OpenCL 1.2: every device has it. Switching converts
  // the maps already on the device, so a switch between trackFrame calls keeps the reference maps valid.
  bool supportsHalfPrecision() const override { return true; }
  void setHalfPrecision(bool enabled) override;
  bool halfPrecision() const override;

  const opencl::DeviceInfo& device() const;

  // Host copies of the device maps, as float (3 per pixel for vertices and normals), row-major, for tests and
  // tools; the same layout as CpuBackend's views.
  const Intrinsics& levelIntrinsics(int level) const;
  std::vector<float> levelDepth(int level);
  std::vector<float> levelVertices(int level);
  std::vector<float> levelNormals(int level);
  std::vector<float> rawMetres();
  const Intrinsics& referenceIntrinsics() const;
  std::vector<float> referenceVertices();
  std::vector<float> referenceNormals();

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace sb
