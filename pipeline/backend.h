#pragma once
// The compute backend: runs the stages on one device and owns the device-side state (the TSDF volume and its
// empty-space skipping structure, the same block-distance grid on both, kernels/raycast.h; the input pyramid,
// the reference maps). The Pipeline drives it; backend_factory.h makes one by name. Two implementations, laid
// out alike, both over kernels/: the CPU backend (pipeline/cpu/, the reference and the oracle in tests) and
// the OpenCL backend (pipeline/opencl/, kernels/cl/ wrappers of the same kernels/ headers).

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <optional>

#include "core/error.h"
#include "core/image.h"
#include "pipeline/pair_noise.h"
#include "pipeline/stages.h"

namespace sb {

constexpr int kPyramidLevels = 3;

// The reduced ICP normal equations of one track + reduce pass (see kernels/track.h, SB_REDUCE_SIZE layout):
// [0] sum e^2 (m^2), [1..6] J^T e, [7..27] upper triangle of J^T J, [28] inliers, [29..31] rejection counts.
using TrackSums = std::array<double, 32>;

// The TSDF volume the backend holds, as the host sees it: read it whole or a box of it, move it (the moving
// volume), and write a box back (a kept map). Its own interface: VolumeWindow (pipeline/volume_window.h) needs
// nothing else of a backend.
class BackendVolume {
 public:
  virtual ~BackendVolume() = default;

  // The volume on the host (2 * R^3 int16, layout in kernels/volume.h: physical voxels, read through the
  // cyclic offset of a moving volume, VolumePlacement::offset); valid until the next call.
  virtual const int16_t* volumeData() = 0;

  // A box of the volume copied to the host: logical voxels first .. first + extent - 1 on each axis, read
  // through the cyclic offset of a moving volume (VolumePlacement::boxPieces), into `out`: 2 * extent[0] *
  // extent[1] * extent[2] int16 (tsdf, weight), x fastest, box voxel (x, y, z) at x + extent[0] * (y +
  // extent[1] * z). Reads only the box (a leaving slab, pipeline/volume_window.h), not the whole volume.
  virtual void readVolumeBox(const std::array<int, 3>& first, const std::array<int, 3>& extent,
                             int16_t* out) = 0;

  // The moving volume (pipeline/volume_placement.h, docs/moving-volume.md): places the volume's corner at
  // `cornerVoxels` (world, voxels; each axis moves by a multiple of VolumePlacement::kBlockVoxels). The voxel
  // addresses take the new cyclic offset, so no voxel is copied; the planes that left are cleared (unobserved)
  // and the empty-space skipping grid follows. Poses given to integrate and raycast and the raycast's maps stay
  // in the world frame. A volume never moved has its corner at 0, the world's origin.
  virtual void moveVolume(const Eigen::Vector3i& cornerVoxels) = 0;

  // The inverse of readVolumeBox: `in` (the same layout) replaces the box's voxels, and the empty-space
  // skipping grid follows (a kept map's surface swapped back into the volume, runtime/map_store.h).
  virtual void writeVolumeBox(const std::array<int, 3>& first, const std::array<int, 3>& extent,
                              const int16_t* in) = 0;
};

// The stages of one frame on one device (the classic names, pipeline/stages.h) and the storage precision of
// their maps. The volume's operations are BackendVolume's.
class ComputeBackend : public BackendVolume {
 public:
  // mm2meters, bilateralFilter, halfSampleRobust, depth2vertex, vertex2normal for a raw frame (full sensor
  // size, `metresPerUnit` metres per raw unit) at the compute size (full size / csr), 3 pyramid levels.
  virtual void preprocess(const DepthRaw& raw, float metresPerUnit, int csr, StageTimes& times) = 0;

  // track + reduce: the input of pyramid `level` moved by cameraToWorld against the reference maps raycast
  // from referencePose (volume frame). The reference must have the current compute size.
  virtual TrackSums track(int level, const Eigen::Isometry3f& cameraToWorld, const Eigen::Isometry3f& referencePose,
                          StageTimes& times) = 0;

  // The structure of the view (pipeline/tracking_quality.h): the output of the last track call, summed per
  // block of `block` x `block` pixels of its level (kernels/track.h's trackBlock), then reduced like track's:
  // [7..27] the blocks' J^T J, [28] the number of blocks holding an inlier, [0..6] 0. block 1 gives track's
  // J^T J. Throws sb::Error when no track ran since the last preprocess or raycast.
  virtual TrackSums blockSums(int block, StageTimes& times) = 0;

  // The pairs of the last track call (the same correspondences) tested with tolerances widened to the depth
  // sensor's noise at each pixel's range (pipeline/pair_noise.h): what a relocaliser's far view can check. Both
  // backends count them with the CPU backend's countPairsInNoise (the OpenCL backend on its maps read back).
  // nullopt where a backend does not count them (this default): the relocaliser then judges tracking's pair
  // agreement. Throws sb::Error when no track ran since the last preprocess or raycast.
  virtual std::optional<PairCounts> pairsInNoise(const DepthNoiseModel& model, StageTimes& times) {
    (void)model;
    (void)times;
    return std::nullopt;
  }
  // Whether pairsInNoise counts them (a kept map's check of the path behind a candidate needs it,
  // runtime/kept_map_history.h: tracking's agreement does not separate a right place from a look-alike there).
  virtual bool countsPairsInNoise() const { return false; }

  // integrate: fuses the last preprocessed frame's depth (compute size, unfiltered) seen from cameraToWorld.
  virtual void integrate(const Eigen::Isometry3f& cameraToWorld, StageTimes& times) = 0;

  // raycast: replaces the reference maps by the model seen from cameraToWorld at full size / csr.
  virtual void raycast(const Eigen::Isometry3f& cameraToWorld, int csr, StageTimes& times) = 0;

  // render: shades the current reference maps (light at `lightPosition`, volume frame, metres).
  virtual Image<uint8_t> render(const Eigen::Vector3f& lightPosition, StageTimes& times) = 0;

  // Reduced precision (architecture.md D3, the paper's "+half"): preprocessed maps (mm2meters output and the
  // pyramid's depth, vertex and normal maps) and the raycast maps stored as half, arithmetic in float. May be
  // switched between any two frames. Backends without it report false and refuse to enable it.
  virtual bool supportsHalfPrecision() const { return false; }
  virtual void setHalfPrecision(bool enabled) {
    if (enabled) throw Error("this compute backend stores float only: half precision needs backend opencl");
  }
  virtual bool halfPrecision() const { return false; }
};

}  // namespace sb
