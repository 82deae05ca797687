#include "pipeline/volume_window.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>

#include "pipeline/volume_placement.h"

namespace sb {

namespace {

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

VolumeWindow::VolumeWindow(const PipelineConfig& config)
    : resolution_(config.volumeResolution),
      size_(config.volumeSize),
      voxelSize_(double(config.volumeSize) / config.volumeResolution),
      threshold_(config.volumeShiftThreshold),
      viewDistance_(config.volumeViewDistance) {}

std::array<int, 3> VolumeWindow::offset() const {
  std::array<int, 3> o{};
  for (int a = 0; a < 3; ++a) o[size_t(a)] = ((corner_[a] % resolution_) + resolution_) % resolution_;
  return o;
}

Eigen::Vector3i VolumeWindow::shiftFor(const Eigen::Isometry3d& T_camera_to_world,
                                       const Eigen::Vector3i& cornerVoxels) const {
  const Eigen::Vector3d view = T_camera_to_world.translation() + viewDistance_ * T_camera_to_world.linear().col(2);
  const Eigen::Vector3d centre = cornerVoxels.cast<double>() * voxelSize_ + Eigen::Vector3d::Constant(0.5 * size_);
  const double block = VolumePlacement::kBlockVoxels * voxelSize_;
  Eigen::Vector3i shift = Eigen::Vector3i::Zero();
  for (int axis = 0; axis < 3; ++axis) {
    const double delta = view[axis] - centre[axis];
    if (!(std::abs(delta) > threshold_)) continue;  // NaN poses never shift
    // Far jumps (a relocalised or wild pose) are capped at one volume side: everything leaves.
    const double blocks = std::clamp(std::round(delta / block), -double(resolution_), double(resolution_));
    shift[axis] = static_cast<int>(blocks) * VolumePlacement::kBlockVoxels;
  }
  return shift;
}

Eigen::Vector3i VolumeWindow::follow(const Eigen::Isometry3d& T_camera_to_world, BackendVolume& backend) {
  if (held_) return Eigen::Vector3i::Zero();
  const Eigen::Vector3i shift = shiftFor(T_camera_to_world, corner_);
  for (int axis = 0; axis < 3; ++axis) {
    const int voxels = shift[axis];
    if (voxels == 0) continue;
    ++stats_.shifts;
    auto start = std::chrono::steady_clock::now();
    if (listener_) {
      // The planes that leave, plus the first one that stays.
      const int leaving = std::min(std::abs(voxels), resolution_);
      const int thickness = std::min(leaving + 1, resolution_);
      VolumeSlab slab;
      slab.resolution = resolution_;
      slab.extent = {resolution_, resolution_, resolution_};
      slab.extent[size_t(axis)] = thickness;
      slab.first[size_t(axis)] = voxels > 0 ? 0 : resolution_ - thickness;
      slab.voxels.resize(2 * size_t(slab.extent[0]) * size_t(slab.extent[1]) * size_t(slab.extent[2]));
      backend.readVolumeBox(slab.first, slab.extent, slab.voxels.data());
      slab.corner = (corner_ + Eigen::Vector3i(slab.first[0], slab.first[1], slab.first[2])).cast<double>() * voxelSize_;
      slab.voxelSize = static_cast<float>(voxelSize_);
      slab.axis = axis;
      slab.shift = stats_.shifts;
      listener_(std::move(slab));
    }
    stats_.slabMs += msSince(start);
    start = std::chrono::steady_clock::now();
    corner_[axis] += voxels;
    backend.moveVolume(corner_);
    stats_.shiftMs += msSince(start);
    if (enterListener_) {  // the planes that came in: at the far side of the move
      const int entering = std::min(std::abs(voxels), resolution_);
      std::array<int, 3> first{}, extent{resolution_, resolution_, resolution_};
      extent[size_t(axis)] = entering;
      first[size_t(axis)] = voxels > 0 ? resolution_ - entering : 0;
      enterListener_(first, extent);
    }
  }
  return shift;
}

Eigen::Vector3i VolumeWindow::placeFor(const Eigen::Isometry3d& T_camera_to_world, BackendVolume& backend) {
  // shiftFor caps a far jump: repeat until the view is within the threshold (a few rounds at most).
  Eigen::Vector3i total = Eigen::Vector3i::Zero();
  for (Eigen::Vector3i shift = shiftFor(T_camera_to_world, corner_); !shift.isZero() && total.norm() < 1e8;
       shift = shiftFor(T_camera_to_world, corner_ + total))
    total += shift;
  if (total.isZero()) return total;
  const auto start = std::chrono::steady_clock::now();
  corner_ += total;
  backend.moveVolume(corner_);
  stats_.shiftMs += msSince(start);
  return total;
}

}  // namespace sb
