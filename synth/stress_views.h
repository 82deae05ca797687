#pragma once
// How a camera view looks to the controller's smooth-surface detector and to ICP, measured on an exact
// (noise-free) render; the stress trajectories use it to place their cameras.
//
// - The detector's windows: the four image quadrants inside a margin (controller/surface_detector.h, whose
//   default margin is 10%); a view is "smooth" there when every window's depth std is small.
// - ICP's conditioning: point-to-plane ICP minimises sum (n . (R p + t - q))^2; per point the Jacobian row
//   is (p x n, n). The 6x6 information matrix is the mean of row^T row over the valid pixels (normals from
//   neighbouring pixels). Its smallest eigenvalue is what ICP sees of the least visible motion: 0 for a
//   single plane (three motions slide freely along it) and for two planes (one), above 0 only when the view
//   holds three independent surface orientations. Rotations are in radians and lever arms in metres.

#include <Eigen/Geometry>
#include <vector>

#include "synth/renderer.h"

namespace sb::synth {

struct ViewMetrics {
  double validFraction = 0.0;  // of the pixels, with a reading (in the sensor's range)
  double maxWindowStdM = 0.0;  // largest depth std over the four quadrant windows, metres
  double minWindowStdM = 0.0;  // smallest, metres
  double minConstraint = 0.0;  // smallest eigenvalue of the per-point ICP information matrix
};

// Renders `T_camera_to_world` without noise with `renderer` (single-threaded) and measures it.
// `marginFraction`: of the width / height, left out of the quadrant windows on every side.
ViewMetrics measureView(const Renderer& renderer, const Eigen::Isometry3d& T_camera_to_world,
                        double marginFraction = 0.1);

// What earlier cameras saw, to tell whether a later view shows a place seen before: their exact renders
// (with `renderer`, whose sensor range applies) and poses.
class SeenSurfaces {
 public:
  explicit SeenSurfaces(const Renderer& renderer) : renderer_(renderer) {}
  void add(const Eigen::Isometry3d& T_camera_to_world);
  size_t views() const { return poses_.size(); }

  // Of the surface points the exact render from `T_camera_to_world` sees, the fraction that some added
  // camera also saw: in its image and range, not hidden (its own render's depth there within `toleranceM`).
  // 0 when the view sees nothing.
  double seenFraction(const Eigen::Isometry3d& T_camera_to_world, double toleranceM = 0.05) const;

 private:
  const Renderer& renderer_;
  std::vector<Eigen::Isometry3d> poses_;  // camera-to-world
  std::vector<DepthMeters> depths_;
};

}  // namespace sb::synth
