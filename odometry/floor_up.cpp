#include "odometry/floor_up.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Eigenvalues>

namespace sb::odometry {

namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
constexpr int kGridColumns = 80;
// Three points of one direction lie on a line within this share of their depth (the middle one off the chord of
// the outer two): a floor at a grazing angle passes, an edge or a step in depth does not.
constexpr double kLineTolerance = 0.03;
constexpr int kPlaneColumns = 160;    // the plane's points: every other pixel at 320 x 240
constexpr double kPlaneBandM = 0.03;  // of the plane: a floor's noise seen at a grazing angle is about a centimetre
constexpr int kPlaneRounds = 3;

struct GridNormals {
  std::vector<Eigen::Vector3d> normals;  // unit, oriented towards `towards`'s hemisphere
  std::vector<Eigen::Vector3d> points;   // where each was taken (camera frame, metres)
  size_t readings = 0;                   // grid points with a reading
};

// The depth image's points, unprojected.
struct Unprojector {
  const DepthRaw& depth;
  double depthScale, fx, fy, cx, cy;
  Unprojector(const DepthRaw& d, double scale, const Intrinsics& k)
      : depth(d), depthScale(scale), fx(k.fx * static_cast<double>(d.width()) / k.width),
        fy(k.fy * static_cast<double>(d.height()) / k.height), cx(k.cx * static_cast<double>(d.width()) / k.width),
        cy(k.cy * static_cast<double>(d.height()) / k.height) {}
  bool operator()(int x, int y, Eigen::Vector3d& p) const {
    const uint16_t raw = depth(x, y);
    if (raw == 0) return false;
    const double z = raw / depthScale;
    p = Eigen::Vector3d((x - cx) / fx * z, (y - cy) / fy * z, z);
    return true;
  }
};

GridNormals gridNormals(const Unprojector& point, const Eigen::Vector3d& towards) {
  GridNormals out;
  const DepthRaw& depth = point.depth;
  const int step = std::max(1, depth.width() / kGridColumns);
  auto onLine = [](const Eigen::Vector3d& a, const Eigen::Vector3d& m, const Eigen::Vector3d& b) {
    return (m - 0.5 * (a + b)).norm() <= kLineTolerance * m.z();
  };
  for (int y = step; y + step < depth.height(); y += step)
    for (int x = step; x + step < depth.width(); x += step) {
      Eigen::Vector3d m, l, r, u, d;
      if (!point(x, y, m)) continue;
      ++out.readings;
      if (!point(x - step, y, l) || !point(x + step, y, r) || !point(x, y - step, u) || !point(x, y + step, d))
        continue;
      if (!onLine(l, m, r) || !onLine(u, m, d)) continue;
      Eigen::Vector3d n = (r - l).cross(d - u);
      const double norm = n.norm();
      if (!(norm > 0.0)) continue;
      n /= norm;
      out.normals.push_back(n.dot(towards) < 0.0 ? -n : n);
      out.points.push_back(m);
    }
  return out;
}

// The mean of the normals within `coneDeg` of `axis` (unit), and how many; none when there are none. `heights`,
// when given: the heights along the mean of the points whose normals were taken.
std::optional<Eigen::Vector3d> meanWithin(const GridNormals& grid, const Eigen::Vector3d& axis, double coneDeg,
                                          size_t& count, std::vector<double>* heights = nullptr) {
  const double minCos = std::cos(coneDeg * kDegToRad);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  count = 0;
  for (const Eigen::Vector3d& n : grid.normals)
    if (n.dot(axis) >= minCos) {
      sum += n;
      ++count;
    }
  if (count == 0 || !(sum.norm() > 0.0)) return std::nullopt;
  const Eigen::Vector3d mean = sum.normalized();
  if (heights)
    for (size_t i = 0; i < grid.normals.size(); ++i)
      if (grid.normals[i].dot(axis) >= minCos) heights->push_back(grid.points[i].dot(mean));
  return mean;
}

// The plane through the points within kPlaneBandM of the plane (`up`, `height`: p . up = height), fitted by least
// squares of their distances (the normal is the smallest eigenvector of their scatter), kPlaneRounds times: the
// normals of neighbouring points lean towards the camera on a floor seen at a grazing angle (the depth's
// quantisation steps: 0.8 degrees on a corridor's floor), a plane through the points themselves does not (0.05).
struct Plane {
  Eigen::Vector3d up;
  double height = 0.0;
  size_t points = 0;
};
std::optional<Plane> fitPlane(const Unprojector& point, Plane plane) {
  const DepthRaw& depth = point.depth;
  const int stride = std::max(1, depth.width() / kPlaneColumns);
  for (int round = 0; round < kPlaneRounds; ++round) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d squares = Eigen::Matrix3d::Zero();
    size_t n = 0;
    for (int y = 0; y < depth.height(); y += stride)
      for (int x = 0; x < depth.width(); x += stride) {
        Eigen::Vector3d p;
        if (!point(x, y, p) || std::abs(p.dot(plane.up) - plane.height) > kPlaneBandM) continue;
        sum += p;
        squares += p * p.transpose();
        ++n;
      }
    if (n < 3) return std::nullopt;
    const Eigen::Vector3d centre = sum / static_cast<double>(n);
    const Eigen::Matrix3d scatter = squares / static_cast<double>(n) - centre * centre.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
    if (eig.info() != Eigen::Success) return std::nullopt;
    Eigen::Vector3d up = eig.eigenvectors().col(0);  // the smallest eigenvalue's
    if (up.dot(plane.up) < 0.0) up = -up;
    plane = Plane{up, centre.dot(up), n};
  }
  return plane;
}

}  // namespace

std::optional<FloorUp> floorUp(const DepthRaw& depth, double depthScale, const Intrinsics& k,
                               const Eigen::Vector3d& assumedUp) {
  if (depth.empty() || !(depthScale > 0.0) || !(assumedUp.norm() > 0.0)) return std::nullopt;
  const Eigen::Vector3d axis = assumedUp.normalized();
  const Unprojector point(depth, depthScale, k);
  const GridNormals grid = gridNormals(point, axis);
  size_t count = 0;
  const std::optional<Eigen::Vector3d> first = meanWithin(grid, axis, kFloorConeDeg, count);
  if (!first) return std::nullopt;
  std::vector<double> heights;
  const std::optional<Eigen::Vector3d> trimmed = meanWithin(grid, *first, kFloorTrimDeg, count, &heights);
  if (!trimmed) return std::nullopt;
  const double share = static_cast<double>(count) / static_cast<double>(std::max<size_t>(1, grid.readings));
  if (share < kFloorMinShare) return std::nullopt;
  // The horizontal surfaces' middle height: the floor where it is the most of them (a table top otherwise: the
  // same normal).
  std::nth_element(heights.begin(), heights.begin() + heights.size() / 2, heights.end());
  const std::optional<Plane> plane = fitPlane(point, Plane{*trimmed, heights[heights.size() / 2], 0});
  if (!plane || std::acos(std::clamp(plane->up.dot(*trimmed), -1.0, 1.0)) > kFloorTrimDeg * kDegToRad)
    return std::nullopt;
  return FloorUp{plane->up, plane->points, share};
}

}  // namespace sb::odometry
