#pragma once
// Ray-casts depth images of a Scene. Per frame, every bounded primitive's bounding box is projected (clipped at
// the camera plane) to a screen rectangle and binned into tiles, so each pixel only tests the primitives
// whose rectangle covers its tile plus the unbounded ones (room walls, planes).
//
// Camera convention (TUM / KinectFusion): pinhole, looks along +z, x right, y down. Depth is the z-distance
// along the optical axis, not the ray length.

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "core/image.h"
#include "core/intrinsics.h"
#include "synth/noise_model.h"
#include "synth/scene.h"

namespace sb::synth {

class Renderer {
 public:
  // Borrows `scene`, which must outlive the renderer.
  Renderer(const Scene& scene, const Intrinsics& intrinsics);

  const Intrinsics& intrinsics() const { return intrinsics_; }

  // Exact depth and incidence for the camera pose. `parallel` splits rows over ThreadPool::global(); pass
  // false when the caller already runs frames in parallel on that pool.
  void renderIdeal(const Eigen::Isometry3d& T_camera_to_world, IdealFrame& out, bool parallel = true) const;

  // Ideal render followed by the sensor model (seeded with `seed`, see frameSeed()).
  void render(const Eigen::Isometry3d& T_camera_to_world, const SensorModel& model, uint64_t seed,
              DepthMeters& out, bool parallel = true) const;

 private:
  struct FrameSetup;  // per-frame primitive transforms and tile bins (renderer.cpp)
  void renderRows(const FrameSetup& setup, int rowBegin, int rowEnd, IdealFrame& out) const;

  const Scene& scene_;
  Intrinsics intrinsics_;
};

}  // namespace sb::synth
