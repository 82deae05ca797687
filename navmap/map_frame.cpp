#include "navmap/map_frame.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

namespace sb::navmap {

namespace {

constexpr double kDegToRad = M_PI / 180.0;

// The rotation from the map frame to the camera frame of a camera pitched down by `pitch` and rolled by
// `roll` (radians) on a level base: camera x right, y down, z forward; map x forward, y left, z up.
Eigen::Matrix3d cameraFromMap(double pitch, double roll) {
  Eigen::Matrix3d level;  // columns: the map's axes in a level camera's frame
  level.col(0) = Eigen::Vector3d(0, 0, 1);   // forward
  level.col(1) = Eigen::Vector3d(-1, 0, 0);  // left
  level.col(2) = Eigen::Vector3d(0, -1, 0);  // up
  // Pitching down turns the camera about its x axis (z towards +y); rolling turns it about its z axis.
  const Eigen::Matrix3d tilt = (Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()) *
                                Eigen::AngleAxisd(-pitch, Eigen::Vector3d::UnitX()))
                                   .toRotationMatrix();
  return tilt.transpose() * level;
}

}  // namespace

MapFrame mapFrameFromMount(const Eigen::Isometry3d& T_world_camera, const CameraMount& mount) {
  Eigen::Isometry3d T_camera_map = Eigen::Isometry3d::Identity();
  T_camera_map.linear() = cameraFromMap(mount.pitchDeg * kDegToRad, mount.rollDeg * kDegToRad);
  T_camera_map.translation() = -T_camera_map.linear() * Eigen::Vector3d(0, 0, mount.heightM);
  MapFrame frame;
  frame.T_world_to_map = (T_world_camera * T_camera_map).inverse();
  char text[128];
  std::snprintf(text, sizeof text, "mount: %.3f m up, pitch %.1f deg, roll %.1f deg", mount.heightM,
                mount.pitchDeg, mount.rollDeg);
  frame.source = text;
  return frame;
}

MapFrame mapFrameFromOdometry(const Eigen::Isometry3d& T_world_camera, const Eigen::Isometry3d& T_camera_to_odom) {
  const Eigen::Isometry3d world_T_odom = T_world_camera * T_camera_to_odom.inverse();
  MapFrame frame;
  frame.T_world_to_map = world_T_odom.inverse();
  frame.source = "odometry";
  return frame;
}

std::string FloorFit::describe() const {
  char text[160];
  std::snprintf(text, sizeof text, "floor %.3f m below the camera, pitch %.1f deg, roll %.1f deg, %.0f%% of points",
                heightM, mount.pitchDeg, mount.rollDeg, 100.0 * inlierShare);
  return text;
}

std::optional<FloorFit> fitFloor(const std::vector<Eigen::Vector3d>& points, const FloorFitParams& params) {
  if (points.size() < 3) return std::nullopt;
  const Eigen::Vector3d up(0, -1, 0);
  const double cosTilt = std::cos(params.maxTiltDeg * kDegToRad);
  std::mt19937 rng(12345);
  std::uniform_int_distribution<size_t> pick(0, points.size() - 1);
  size_t bestCount = 0;
  Eigen::Vector3d bestNormal = Eigen::Vector3d::Zero();
  double bestD = 0.0;
  for (int it = 0; it < params.iterations; ++it) {
    const Eigen::Vector3d& a = points[pick(rng)];
    const Eigen::Vector3d& b = points[pick(rng)];
    const Eigen::Vector3d& c = points[pick(rng)];
    Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-9) continue;
    n.normalize();
    if (n.dot(up) < 0) n = -n;
    if (n.dot(up) < cosTilt) continue;
    const double d = -n.dot(a);  // plane n.x + d = 0; the camera at the origin lies d above it
    if (d < params.minHeightM) continue;
    size_t count = 0;
    for (const Eigen::Vector3d& p : points) count += std::abs(n.dot(p) + d) <= params.inlierM;
    if (count > bestCount) bestCount = count, bestNormal = n, bestD = d;
  }
  if (bestCount < params.minInlierShare * double(points.size()) || bestCount < 3) return std::nullopt;
  // Refine with a least-squares plane through the inliers.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> inliers;
  for (const Eigen::Vector3d& p : points)
    if (std::abs(bestNormal.dot(p) + bestD) <= params.inlierM) inliers.push_back(p), mean += p;
  mean /= double(inliers.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : inliers) cov += (p - mean) * (p - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);
  Eigen::Vector3d n = solver.eigenvectors().col(0).normalized();
  if (n.dot(up) < 0) n = -n;
  FloorFit fit;
  fit.normalCamera = n;
  fit.heightM = -n.dot(mean);  // the camera (the origin) above the plane n.x = n.mean
  fit.inlierShare = double(inliers.size()) / double(points.size());
  // The mount with this floor: up in the camera frame is (-sin roll, -cos roll cos pitch, -cos roll sin pitch)
  // (cameraFromMap applied to the map's z).
  fit.mount.heightM = fit.heightM;
  fit.mount.pitchDeg = std::atan2(-n.z(), -n.y()) / kDegToRad;
  fit.mount.rollDeg = std::asin(std::clamp(-n.x(), -1.0, 1.0)) / kDegToRad;
  return fit;
}

}  // namespace sb::navmap
