// Tracking quality: the conditioning of the ICP normal matrix sees which motions the geometry fixes, whatever
// the volume origin and the scene's scale.

#include <catch2/catch.hpp>
#include <random>

#include "pipeline/tracking_quality.h"

namespace {

struct Point {
  Eigen::Vector3d p, n;  // world position and unit normal
};

// The reduced sums of point-to-plane rows [n, p x n] (kernels/track.h layout, zero residuals).
sb::TrackSums sums(const std::vector<Point>& points) {
  sb::TrackSums s{};
  for (const Point& q : points) {
    Eigen::Matrix<double, 6, 1> j;
    j << q.n, q.p.cross(q.n);
    int k = 7;
    for (int a = 0; a < 6; ++a)
      for (int b = a; b < 6; ++b) s[size_t(k++)] += j(a) * j(b);
    s[28] += 1;
  }
  return s;
}

// A camera at `c` looking along +z; `planes` of the box corner it sees: the wall ahead (z = c.z + 2), the
// floor (y = c.y + 1.2), the side wall (x = c.x + 1.5); normals point back at the camera, noisy by `noise`.
std::vector<Point> scene(const Eigen::Vector3d& c, int planes, double noise, double scale = 1.0) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> g(0.0, noise);
  std::vector<Point> pts;
  for (int i = 0; i < 3000; ++i) {
    const int which = i % planes;
    Eigen::Vector3d p, n;
    if (which == 0) { p = {u(rng), u(rng) * 0.8, 2.0}; n = {0, 0, -1}; }
    if (which == 1) { p = {u(rng), 1.2, 1.0 + u(rng) * 0.8}; n = {0, -1, 0}; }
    if (which == 2) { p = {1.5, u(rng) * 0.8, 1.0 + u(rng) * 0.8}; n = {-1, 0, 0}; }
    n += Eigen::Vector3d(g(rng), g(rng), g(rng));
    pts.push_back({c + scale * p, n.normalized()});
  }
  return pts;
}

Eigen::Isometry3d at(const Eigen::Vector3d& c) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = c;
  return T;
}

}  // namespace

TEST_CASE("a single plane leaves motion unconstrained; three planes fix it", "[pipeline][quality]") {
  const Eigen::Vector3d c(2.5, 2.5, 1.5);
  const sb::TrackingQuality wall = sb::trackingQuality(sums(scene(c, 1, 0.02)), at(c), 0.002);
  CHECK(wall.known);
  CHECK_FALSE(wall.constrained);
  CHECK(wall.conditioning < 0.002);
  const std::string weakest = sb::weakDirectionName(wall.weakest);
  CHECK((weakest == "tx" || weakest == "ty" || weakest == "rz"));  // sliding along the wall or turning about it
  const sb::TrackingQuality corner = sb::trackingQuality(sums(scene(c, 3, 0.02)), at(c), 0.002);
  CHECK(corner.constrained);
  CHECK(corner.conditioning > 0.05);
  // Wall + floor: sideways sliding (camera x) is the free motion.
  const sb::TrackingQuality two = sb::trackingQuality(sums(scene(c, 2, 0.0)), at(c), 0.002);
  CHECK_FALSE(two.constrained);
  CHECK(sb::weakDirectionName(two.weakest) == std::string("tx"));
}

TEST_CASE("conditioning does not depend on the volume origin or the scene's scale", "[pipeline][quality]") {
  const Eigen::Vector3d c1(0.5, 0.5, 0.5), c2(4.0, 1.0, 3.0);
  const double a = sb::trackingQuality(sums(scene(c1, 3, 0.01)), at(c1), 0.002).conditioning;
  const double b = sb::trackingQuality(sums(scene(c2, 3, 0.01)), at(c2), 0.002).conditioning;
  CHECK(a == Approx(b).epsilon(1e-6));
  const double scaled = sb::trackingQuality(sums(scene(c1, 3, 0.01, 2.5)), at(c1), 0.002).conditioning;
  CHECK(a == Approx(scaled).epsilon(1e-6));
}

TEST_CASE("too few inliers are not constrained", "[pipeline][quality]") {
  sb::TrackSums s{};
  s[28] = 3;
  const sb::TrackingQuality q = sb::trackingQuality(s, Eigen::Isometry3d::Identity(), 0.002);
  CHECK(q.known);
  CHECK_FALSE(q.constrained);
  CHECK(q.conditioning == 0.0);
}
