#pragma once
// What the OpenCL backend keeps on the device: the program variants (float and half map storage, built from
// the embedded sources with -D options), the buffers (allocated once for the full sensor size) and the
// transfers. Internal to pipeline/opencl/.

#include <array>
#include <memory>
#include <utility>
#include <vector>

#include "core/thread_pool.h"
#include "kernels/common.h"
#include "pipeline/opencl/launcher.h"
#include "pipeline/opencl/opencl_backend.h"
#include "pipeline/ray_bounds.h"
#include "pipeline/volume_placement.h"

namespace sb {

namespace opencl {

constexpr size_t kReduceGroup = 64;          // work-items per reduce group (SB_REDUCE_GROUP in track.cl)
constexpr size_t kPixelsPerReduceItem = 32;  // pixels each reduce work-item sums (fewer groups for small images)
constexpr size_t kMaxReduceGroups = 1024;

// One build of the program and its kernels.
struct Kernels {
  // `sourceDir`: empty for the embedded program, else the directory to read it from.
  Kernels(const Launcher& launcher, const DeviceInfo& device, bool halfStorage, const std::string& sourceDir);

  Program program;
  Kernel mm2meters, bilateralFilter, halfSampleRobust, depth2vertex, vertex2normal;
  Kernel track, block, reduce, reduceFinal;
  Kernel initVolume, integrate, clearSlab, surfaceMask;
  Kernel raycast, offsetVertex, render;
  Kernel halfToFloat, floatToHalf;
};

}  // namespace opencl

struct OpenClBackend::State {
  struct Level {
    Intrinsics k;
    opencl::Buffer depth, vertex, normal;
  };

  State(const PipelineConfig& config, const Intrinsics& fullSize, const opencl::DeviceInfo& device);

  const opencl::Kernels& kernels() { return variant(half); }
  const opencl::Kernels& variant(bool halfStorage);  // built on first use

  void upload(const DepthRaw& raw);  // into `raw` through a mapping
  void useBilateralTaps();           // `gaussian` and tapsRadius (bilateral_taps.h), written once
  void read(const opencl::Buffer& buffer, void* out, size_t bytes);
  TrackSums readSums();
  // reduce + reduceFinal over `rows` track rows (kernels/track.h layout) of `rowsBuffer`; the sums read back.
  TrackSums reduceRows(const opencl::Buffer& rowsBuffer, int rows);
  std::vector<float> readMap(const opencl::Buffer& buffer, size_t count);  // count values of the current storage
  // The empty-space skipping grid of the volume as it is now: surfaceMaskKernel, the masks read back, their
  // distances (pipeline/block_distance.h, on the host) written to blockDistance. Queued kernels are booked to
  // `stage` at the caller's finish().
  void updateSkipping(Stage stage);
  void convert(opencl::Buffer& buffer, size_t count, bool toHalf);
  // Every map buffer with the number of values it currently holds.
  std::vector<std::pair<opencl::Buffer*, size_t>> maps();
  static size_t pixels(const Intrinsics& k, bool valid) { return valid ? size_t(k.width) * k.height : 0; }

  PipelineConfig config;
  Intrinsics full;
  opencl::DeviceInfo device;
  opencl::Launcher launcher;
  std::array<std::unique_ptr<opencl::Kernels>, 2> variants;  // [0] float storage, [1] half storage
  bool half = false;

  opencl::Buffer raw;       // the sensor frame, CL_MEM_ALLOC_HOST_PTR
  opencl::Buffer gaussian;  // bilateralFilter spatial weights
  bool tapsWritten = false;
  int tapsRadius = 0;
  opencl::Buffer depth;     // mm2meters output (compute size), read by integrate
  std::array<Level, kPyramidLevels> levels;
  opencl::Buffer trackOut, partial, sums;
  opencl::Buffer blockOut;                   // blockKernel's rows (as many as pixels: block 1 at most)
  Intrinsics trackK;                         // the level of the last track call
  int trackLevel = 0;                        // its pyramid level
  SbMat34 trackCameraToWorld{}, trackWorldToRefPixel{};  // its transforms (kernels/track.h's track())
  bool hasTrack = false;                     // trackOut holds a track since the last preprocess or raycast
  opencl::Buffer referenceVertex, referenceNormal;
  opencl::Buffer volume;
  // Empty-space skipping, blocks of (1 << SB_SKIP_SHIFT)^3 voxels (kernels/raycast.h): per block its surface
  // mask and its distance to the nearest block with surface; their host copies, and a pool of one thread (the
  // calling one) for the distance transform.
  opencl::Buffer blockMasks, blockDistance;
  std::vector<uint8_t> blockMasksHost, blockDistanceHost;
  ThreadPool skipPool{1};
  // The raycast's ray bounds (pipeline/ray_bounds.h), made on the host and written to the device.
  RayBounds rayBounds;
  opencl::Buffer rayBoundsBuffer;
  opencl::Buffer image;    // render output
  opencl::Buffer scratch;  // precision conversions, 3 floats per full-size pixel

  Intrinsics computeK, referenceK;
  bool hasFrame = false, hasReference = false;
  std::vector<int16_t> volumeHost;
  bool volumeOnHost = false;
  VolumePlacement placement;  // the moving volume's corner and cyclic offset (fixed: 0)
};

}  // namespace sb
