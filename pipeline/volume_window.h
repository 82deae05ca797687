#pragma once
// The moving volume's policy (docs/moving-volume.md; after Kintinuous, Whelan et al. 2012): after each frame
// the window looks at the centre of the camera's view; when it lies farther than a threshold from the
// volume's centre on some axis, the volume shifts along that axis by the whole blocks that bring the view
// centre back to the centre. The backend does the shift as a cyclic buffer (BackendVolume::moveVolume: a new
// address offset, the planes that left cleared, no voxel copied); before it, a copy of the slab that leaves
// is handed to a listener (the run meshes it into the whole run's map). Poses stay in the world frame, the
// frame of the first volume: a client never sees a shift, and a run that never shifts is exactly the
// fixed-volume run.
//
//   VolumeWindow window(config);
//   window.setSlabListener([&](VolumeSlab&& slab) { ... mesh it (runtime/map_slabs.h) ... });
//   after every frame: window.follow(T_camera_to_world, backend);

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "pipeline/backend.h"
#include "pipeline/config.h"

namespace sb {

// A box of voxels about to leave the volume, copied out of it before the shift clears them
// (BackendVolume::readVolumeBox: only the box is read): logical voxels first .. first + extent - 1 of the
// volume. It holds one voxel more than leaves, on the side of what stays, so that the cells between the slab
// and the rest are meshed once, with the slab. The listener owns it (it may keep it: the volume is cleared
// and reused at once).
struct VolumeSlab {
  // 2 * extent[0] * extent[1] * extent[2] int16 (tsdf, weight), x fastest: box voxel (x, y, z) at
  // x + extent[0] * (y + extent[1] * z), the layout of kernels/volume.h without the offset.
  std::vector<int16_t> voxels;
  int resolution = 0;          // of the volume it left
  std::array<int, 3> first{};  // the box, logical voxels of the volume
  std::array<int, 3> extent{};
  Eigen::Vector3d corner = Eigen::Vector3d::Zero();  // world, metres: the lower corner of voxel `first`
  float voxelSize = 0.0f;           // metres
  int axis = 0;                     // the axis of the shift that makes it leave
  size_t shift = 0;                 // 1-based count of the window's shifts

  size_t bytes() const { return voxels.size() * sizeof(int16_t); }
};

struct VolumeWindowStats {
  size_t shifts = 0;     // per axis: a shift along x and y in one frame counts 2
  double shiftMs = 0.0;  // the backend's moveVolume (clear, skipping grid), summed
  double slabMs = 0.0;   // reading the slabs out of the volume and the listener (on this thread), summed
};

class VolumeWindow {
 public:
  explicit VolumeWindow(const PipelineConfig& config);

  // The shift (whole blocks, voxels per axis) that the view from `T_camera_to_world` (world frame) asks of a
  // volume whose corner is at `cornerVoxels`; zero when the view centre is within the threshold on every axis.
  Eigen::Vector3i shiftFor(const Eigen::Isometry3d& T_camera_to_world, const Eigen::Vector3i& cornerVoxels) const;

  // Shifts `backend`'s volume when the view is far from its centre (shiftFor), axis by axis, each slab to the
  // listener first; returns the shift in voxels per axis (0: none).
  Eigen::Vector3i follow(const Eigen::Isometry3d& T_camera_to_world, BackendVolume& backend);

  // Called with every slab that leaves (a copy, read before it is cleared), on the thread that calls follow.
  // None: slabs are neither read nor kept.
  void setSlabListener(std::function<void(VolumeSlab&&)> listener) { listener_ = std::move(listener); }

  // The box of the volume that a shift of follow() brought in (logical voxels first .. first + extent - 1 of
  // the volume at its new corner, cleared): a kept map swaps its surface back in there (runtime/map_store.h).
  using EnterListener = std::function<void(const std::array<int, 3>& first, const std::array<int, 3>& extent)>;
  void setEnterListener(EnterListener listener) { enterListener_ = std::move(listener); }

  // Places the volume where follow() would bring it for a camera at `T_camera_to_world`, in one move, handing
  // nothing to either listener: what leaves is dropped and what comes in is cleared (a kept map's volume,
  // whose surface its store holds, placed for a relocalisation candidate). Returns the shift in voxels.
  Eigen::Vector3i placeFor(const Eigen::Isometry3d& T_camera_to_world, BackendVolume& backend);
  // While held, follow() does not move the volume (a kept map's volume placed for a candidate, while the pose
  // is held elsewhere until the run is localised).
  void setHeld(bool held) { held_ = held; }

  // The world position of the volume's corner, voxels and metres; the cyclic offset.
  const Eigen::Vector3i& cornerVoxels() const { return corner_; }
  Eigen::Vector3d cornerMetres() const { return corner_.cast<double>() * voxelSize_; }
  std::array<int, 3> offset() const;
  const VolumeWindowStats& stats() const { return stats_; }

 private:
  int resolution_;
  double size_;           // metres
  double voxelSize_;      // metres
  double threshold_;      // metres
  double viewDistance_;   // metres
  Eigen::Vector3i corner_ = Eigen::Vector3i::Zero();
  std::function<void(VolumeSlab&&)> listener_;
  EnterListener enterListener_;
  bool held_ = false;
  VolumeWindowStats stats_;
};

}  // namespace sb
