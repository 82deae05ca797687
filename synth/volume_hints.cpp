#include "synth/volume_hints.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "synth/renderer.h"

namespace sb::synth {

namespace {

double percentile(std::vector<double>& values, double q) {
  const size_t i = static_cast<size_t>(q * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(i), values.end());
  return values[i];
}

}  // namespace

VolumeHints estimateVolumeHints(const Scene& scene, const Trajectory& trajectory, const Intrinsics& intrinsics,
                                const SensorModel& sensor, const VolumeHintParams& params) {
  const Intrinsics k = intrinsics.scaled(params.subsample);
  const Renderer renderer(scene, k);
  SensorModel exact = sensor;
  exact.noise = false;
  const Eigen::Isometry3d T_first_from_world = trajectory.front().T_camera_to_world.inverse();
  const size_t step = std::max<size_t>(1, trajectory.size() / params.sampledFrames);

  std::array<std::vector<double>, 3> coords;
  DepthMeters depth;
  for (size_t f = 0; f < trajectory.size(); f += step) {
    const Eigen::Isometry3d T_first_from_camera = T_first_from_world * trajectory[f].T_camera_to_world;
    for (int a = 0; a < 3; ++a) coords[a].push_back(T_first_from_camera.translation()[a]);
    renderer.render(trajectory[f].T_camera_to_world, exact, 0, depth);
    for (int y = 0; y < k.height; ++y) {
      for (int x = 0; x < k.width; ++x) {
        const double z = depth(x, y);
        if (z <= 0.0) continue;
        const Eigen::Vector3d p = T_first_from_camera * Eigen::Vector3d((x - k.cx) / k.fx * z, (y - k.cy) / k.fy * z, z);
        for (int a = 0; a < 3; ++a) coords[a].push_back(p[a]);
      }
    }
  }
  Eigen::Vector3d lo, hi;
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::min(0.0, percentile(coords[a], params.lowPercentile)) - params.paddingM;
    hi[a] = std::max(0.0, percentile(coords[a], params.highPercentile)) + params.paddingM;
  }
  if (params.holdPath) {
    for (const TimedPose& pose : trajectory) {
      const Eigen::Vector3d c = T_first_from_world * pose.position();
      lo = lo.cwiseMin(c - Eigen::Vector3d::Constant(params.paddingM));
      hi = hi.cwiseMax(c + Eigen::Vector3d::Constant(params.paddingM));
    }
  }
  VolumeHints hints;
  const double extent = (hi - lo).maxCoeff();
  hints.sizeM = std::clamp(std::ceil(extent / params.roundingM) * params.roundingM, params.minSizeM, params.maxSizeM);
  for (int a = 0; a < 3; ++a) {
    const double cubeMin = 0.5 * (lo[a] + hi[a]) - 0.5 * hints.sizeM;
    hints.initialPosition[a] = std::clamp(-cubeMin / hints.sizeM, 0.0, 1.0);
  }
  return hints;
}

}  // namespace sb::synth
