#include "synth/stress_views.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace sb::synth {

namespace {

constexpr double kMaxNeighbourJump = 0.05;  // of the depth: a larger step to a neighbour is a discontinuity

// Depth std (metres) over each quadrant window inside the margin, zero-depth pixels left out.
void windowStds(const DepthMeters& depth, double marginFraction, ViewMetrics& out) {
  const int w = depth.width(), h = depth.height();
  const int x0 = static_cast<int>(marginFraction * w), x1 = w - x0;
  const int y0 = static_cast<int>(marginFraction * h), y1 = h - y0;
  const int midX = (x0 + x1) / 2, midY = (y0 + y1) / 2;
  out.maxWindowStdM = 0.0;
  out.minWindowStdM = 1e9;
  for (int window = 0; window < 4; ++window) {
    double sum = 0, sumSq = 0;
    int n = 0;
    for (int y = window / 2 ? midY : y0; y < (window / 2 ? y1 : midY); ++y)
      for (int x = window % 2 ? midX : x0; x < (window % 2 ? x1 : midX); ++x)
        if (const double z = depth(x, y); z > 0) sum += z, sumSq += z * z, ++n;
    const double std = n ? std::sqrt(std::max(0.0, sumSq / n - (sum / n) * (sum / n))) : 0.0;
    out.maxWindowStdM = std::max(out.maxWindowStdM, std);
    out.minWindowStdM = std::min(out.minWindowStdM, std);
  }
}

double minConstraint(const DepthMeters& depth, const Intrinsics& k) {
  auto point = [&](int x, int y) {
    const double z = depth(x, y);
    return Eigen::Vector3d((x - k.cx) / k.fx * z, (y - k.cy) / k.fy * z, z);
  };
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  size_t points = 0;
  for (int y = 0; y + 1 < depth.height(); ++y) {
    for (int x = 0; x + 1 < depth.width(); ++x) {
      const double z = depth(x, y);
      if (z <= 0 || depth(x + 1, y) <= 0 || depth(x, y + 1) <= 0) continue;
      const Eigen::Vector3d p = point(x, y), right = point(x + 1, y) - p, down = point(x, y + 1) - p;
      if (right.norm() > kMaxNeighbourJump * z || down.norm() > kMaxNeighbourJump * z) continue;
      const Eigen::Vector3d n = right.cross(down).normalized();
      Eigen::Matrix<double, 6, 1> row;
      row << p.cross(n), n;
      information += row * row.transpose();
      ++points;
    }
  }
  if (points == 0) return 0.0;
  information /= static_cast<double>(points);
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>(information, Eigen::EigenvaluesOnly)
      .eigenvalues()[0];
}

}  // namespace

ViewMetrics measureView(const Renderer& renderer, const Eigen::Isometry3d& T_camera_to_world,
                        double marginFraction) {
  SensorModel exact;
  exact.noise = false;
  DepthMeters depth;
  renderer.render(T_camera_to_world, exact, 0, depth, /*parallel=*/false);
  ViewMetrics m;
  size_t valid = 0;
  for (float z : depth.pixels()) valid += z > 0.f;
  m.validFraction = depth.size() ? static_cast<double>(valid) / depth.size() : 0.0;
  windowStds(depth, marginFraction, m);
  m.minConstraint = minConstraint(depth, renderer.intrinsics());
  return m;
}

namespace {

DepthMeters exactDepth(const Renderer& renderer, const Eigen::Isometry3d& T_camera_to_world) {
  SensorModel exact;
  exact.noise = false;
  DepthMeters depth;
  renderer.render(T_camera_to_world, exact, 0, depth, /*parallel=*/false);
  return depth;
}

}  // namespace

void SeenSurfaces::add(const Eigen::Isometry3d& T_camera_to_world) {
  poses_.push_back(T_camera_to_world);
  depths_.push_back(exactDepth(renderer_, T_camera_to_world));
}

double SeenSurfaces::seenFraction(const Eigen::Isometry3d& T_camera_to_world, double toleranceM) const {
  const Intrinsics& k = renderer_.intrinsics();
  const DepthMeters depth = exactDepth(renderer_, T_camera_to_world);
  std::vector<Eigen::Isometry3d> T_earlier_from_view;
  for (const Eigen::Isometry3d& T : poses_) T_earlier_from_view.push_back(T.inverse() * T_camera_to_world);
  size_t points = 0, seen = 0;
  for (int y = 0; y < k.height; ++y) {
    for (int x = 0; x < k.width; ++x) {
      const double z = depth(x, y);
      if (z <= 0.0) continue;
      ++points;
      const Eigen::Vector3d p((x - k.cx) / k.fx * z, (y - k.cy) / k.fy * z, z);
      for (size_t c = 0; c < poses_.size(); ++c) {
        const Eigen::Vector3d q = T_earlier_from_view[c] * p;
        if (q.z() <= 0.0) continue;
        const int u = static_cast<int>(std::lround(k.fx * q.x() / q.z() + k.cx));
        const int v = static_cast<int>(std::lround(k.fy * q.y() / q.z() + k.cy));
        if (u < 0 || v < 0 || u >= k.width || v >= k.height) continue;
        const double there = depths_[c](u, v);
        if (there > 0.0 && std::abs(there - q.z()) <= toleranceM) {
          ++seen;
          break;
        }
      }
    }
  }
  return points ? static_cast<double>(seen) / static_cast<double>(points) : 0.0;
}

}  // namespace sb::synth
