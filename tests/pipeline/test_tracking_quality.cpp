// Tracking quality: the conditioning of the ICP normal matrix sees which motions the geometry fixes, whatever
// the volume origin and the scene's scale.

#include <catch2/catch.hpp>
#include <random>

#include "pipeline/icp_solve.h"
#include "pipeline/tracking_quality.h"

namespace {

struct Point {
  Eigen::Vector3d p, n;  // world position and unit normal as measured (noisy)
  Eigen::Vector3d trueN;  // the plane's normal
};

// The reduced sums of point-to-plane rows [n, p x n] (kernels/track.h layout, measured normals) whose
// residuals are those of the motion `truth` (twist) against the true planes plus a noise of `noise` metres.
sb::TrackSums sums(const std::vector<Point>& points, const sb::Twist& truth = sb::Twist::Zero(), double noise = 0) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0.0, noise > 0 ? noise : 1.0);
  sb::TrackSums s{};
  for (const Point& q : points) {
    Eigen::Matrix<double, 6, 1> j;
    j << q.n, q.p.cross(q.n);
    Eigen::Matrix<double, 6, 1> jTrue;
    jTrue << q.trueN, q.p.cross(q.trueN);
    const double e = jTrue.dot(truth) + (noise > 0 ? g(rng) : 0.0);
    s[0] += e * e;
    for (int a = 0; a < 6; ++a) s[size_t(1 + a)] += j(a) * e;
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
    Eigen::Vector3d p = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::UnitZ();
    if (which == 0) { p = {u(rng), u(rng) * 0.8, 2.0}; n = {0, 0, -1}; }
    if (which == 1) { p = {u(rng), 1.2, 1.0 + u(rng) * 0.8}; n = {0, -1, 0}; }
    if (which == 2) { p = {1.5, u(rng) * 0.8, 1.0 + u(rng) * 0.8}; n = {-1, 0, 0}; }
    const Eigen::Vector3d trueN = n;
    n += Eigen::Vector3d(g(rng), g(rng), g(rng));
    pts.push_back({c + scale * p, n.normalized(), trueN});
  }
  return pts;
}

// The quality with every pixel its own block (blockSums at block 1 gives the ICP sums).
sb::TrackingQuality quality(const sb::TrackSums& s, const Eigen::Isometry3d& pose, double minConditioning) {
  return sb::trackingQuality(s, s, pose, minConditioning);
}

Eigen::Isometry3d at(const Eigen::Vector3d& c) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = c;
  return T;
}

}  // namespace

TEST_CASE("a single plane leaves motion unconstrained; three planes fix it", "[pipeline][quality]") {
  const Eigen::Vector3d c(2.5, 2.5, 1.5);
  const sb::TrackingQuality wall = quality(sums(scene(c, 1, 0.02)), at(c), 0.002);
  CHECK(wall.known);
  CHECK_FALSE(wall.constrained);
  CHECK(wall.conditioning < 0.002);
  const std::string weakest = sb::weakDirectionName(wall.weakest);
  CHECK((weakest == "tx" || weakest == "ty" || weakest == "rz"));  // sliding along the wall or turning about it
  const sb::TrackingQuality corner = quality(sums(scene(c, 3, 0.02)), at(c), 0.002);
  CHECK(corner.constrained);
  CHECK(corner.conditioning > 0.05);
  // Wall + floor: sideways sliding (camera x) is the free motion.
  const sb::TrackingQuality two = quality(sums(scene(c, 2, 0.0)), at(c), 0.002);
  CHECK_FALSE(two.constrained);
  CHECK(sb::weakDirectionName(two.weakest) == std::string("tx"));
}

TEST_CASE("conditioning does not depend on the volume origin or the scene's scale", "[pipeline][quality]") {
  const Eigen::Vector3d c1(0.5, 0.5, 0.5), c2(4.0, 1.0, 3.0);
  const double a = quality(sums(scene(c1, 3, 0.01)), at(c1), 0.002).conditioning;
  const double b = quality(sums(scene(c2, 3, 0.01)), at(c2), 0.002).conditioning;
  CHECK(a == Approx(b).epsilon(1e-6));
  const double scaled = quality(sums(scene(c1, 3, 0.01, 2.5)), at(c1), 0.002).conditioning;
  CHECK(a == Approx(scaled).epsilon(1e-6));
}

TEST_CASE("too few inliers are not constrained", "[pipeline][quality]") {
  sb::TrackSums s{};
  s[28] = 3;
  const sb::TrackingQuality q = quality(s, Eigen::Isometry3d::Identity(), 0.002);
  CHECK(q.known);
  CHECK_FALSE(q.constrained);
  CHECK(q.conditioning == 0.0);
}

// Solution remapping along free motions (IcpStart::holdBelowConditioning): in front of a wall the update
// along the wall is noise over a near-zero eigenvalue; holding it keeps the start pose there.
TEST_CASE("holding free motions: no slide along a wall, the same update where every motion is fixed",
          "[pipeline][quality]") {
  const Eigen::Vector3d c(2.5, 2.5, 1.5);
  sb::Twist approach;  // 2 cm towards the wall (world z) and 1 cm sideways (world x, along the wall)
  approach << 0.01, 0.0, 0.02, 0.0, 0.0, 0.0;
  const sb::TrackSums wall = sums(scene(c, 1, 0.02), approach, 0.003);
  sb::Twist plain, held;
  REQUIRE(sb::solveIcpUpdate(wall, plain));
  REQUIRE(sb::solveIcpUpdateHolding(wall, at(c), 0.0006, held));
  // The plain solve moves along the wall by noise: the sideways centimetre is not in the data, and what it
  // finds there instead is the noise over the tiny eigenvalues of the wall's tangent directions (4.3 mm on
  // x86-64, 0.7 mm on armhf: near-null directions round differently), so only its difference is checked.
  CHECK((plain - held).norm() > 1e-5);
  // Held: along the wall (x, y) and the rotation about its normal (z) nothing moves; towards it, the 2 cm.
  CHECK(std::abs(held(0)) < 1e-3);
  CHECK(std::abs(held(1)) < 1e-3);
  CHECK(std::abs(held(5)) < 1e-3);
  CHECK(held(2) == Approx(0.02).margin(2e-3));

  // Three planes fix every motion: holding changes nothing but rounding.
  sb::Twist motion;
  motion << 0.01, -0.02, 0.015, 0.01, -0.005, 0.02;
  const sb::TrackSums corner = sums(scene(c, 3, 0.02), motion, 0.001);
  REQUIRE(sb::solveIcpUpdate(corner, plain));
  REQUIRE(sb::solveIcpUpdateHolding(corner, at(c), 0.0006, held));
  CHECK((plain - held).norm() < 1e-9);
  CHECK((plain - motion).norm() < 2e-3);
  // holdBelow 0 is the plain solve, bit for bit.
  REQUIRE(sb::solveIcpUpdateHolding(wall, at(c), 0.0, held));
  sb::Twist again;
  REQUIRE(sb::solveIcpUpdate(wall, again));
  CHECK(held == again);
}

// A planar base's height and tilt as a prior in the solve (IcpStart::prior, icp_solve.h PlanarPrior): where the view
// leaves them free (a wall ahead: the height and the roll about the optical axis) the prior holds them; where the view
// fixes them it hardly moves the solve.
TEST_CASE("a planar prior holds the height and tilt a wall leaves free, and hardly moves what the view fixes",
          "[pipeline][quality]") {
  const Eigen::Vector3d c(2.5, 2.5, 1.5);
  const Eigen::Vector3d up(0, -1, 0);  // the camera's y points down
  sb::Twist approach;                  // 2 cm towards the wall (world z) and 1 cm down (world y, along the wall)
  approach << 0.0, 0.01, 0.02, 0.0, 0.0, 0.0;
  const sb::TrackSums wall = sums(scene(c, 1, 0.02), approach, 0.003);
  sb::PlanarPrior prior{at(c), up, 0.01};
  sb::Twist plain, held;
  REQUIRE(sb::solveIcpUpdate(wall, plain));
  REQUIRE(sb::solveIcpUpdateHolding(wall, at(c), 0.0, held, &prior));
  // The camera stays at the prior's height; towards the wall the view's 2 cm stands.
  CHECK(std::abs(held(1)) < 1e-3);
  CHECK(held(2) == Approx(0.02).margin(2e-3));

  // Estimated 5 cm below the prior's height and rolled 1 degree about the optical axis: pulled back, the view
  // having nothing to say about either.
  Eigen::Isometry3d low = at(c + Eigen::Vector3d(0, 0.05, 0));
  low.linear() = Eigen::AngleAxisd(1.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  REQUIRE(sb::solveIcpUpdateHolding(sums(scene(c, 1, 0.02), sb::Twist::Zero(), 0.003), low, 0.0, held, &prior));
  const Eigen::Isometry3d moved = sb::twistToTransform(held) * low;
  CHECK(moved.translation().y() == Approx(c.y()).margin(2e-3));
  CHECK(Eigen::AngleAxisd(moved.linear()).angle() * 180.0 / M_PI < 0.1);
  // The rotation about up (the heading) is the wheels' or the view's, never the prior's.
  Eigen::Isometry3d turned = at(c);
  turned.linear() = Eigen::AngleAxisd(1.0 * M_PI / 180.0, up).toRotationMatrix();
  sb::Twist none;
  REQUIRE(sb::solveIcpUpdateHolding(sums(scene(c, 1, 0.02), sb::Twist::Zero(), 0.0), turned, 0.0, none, &prior));
  CHECK(std::abs(none(4)) < 1e-4);

  // Three planes fix every motion: the prior, a stiffness far below theirs, moves the solve by millimetres.
  sb::Twist motion;
  motion << 0.01, -0.02, 0.015, 0.01, -0.005, 0.02;
  const sb::TrackSums corner = sums(scene(c, 3, 0.02), motion, 0.001);
  REQUIRE(sb::solveIcpUpdate(corner, plain));
  REQUIRE(sb::solveIcpUpdateHolding(corner, at(c), 0.0, held, &prior));
  CHECK((plain - motion).norm() < 2e-3);
  // Of the camera (the twists turn about the world's origin): its centre and its rotation against the truth's. The
  // 1.3 degrees of tilt in `motion` are pulled back by about k / (c + k), c the corner's conditioning: 0.12 degrees.
  const Eigen::Isometry3d truth = sb::twistToTransform(motion) * at(c), solved = sb::twistToTransform(held) * at(c);
  CHECK((solved.translation() - truth.translation()).norm() < 3e-3);
  CHECK(Eigen::AngleAxisd(solved.linear() * truth.linear().transpose()).angle() * 180.0 / M_PI < 0.2);
  // A prior of no weight is the plain solve, bit for bit.
  prior.conditioning = 0.0;
  REQUIRE(sb::solveIcpUpdateHolding(wall, at(c), 0.0, held, &prior));
  REQUIRE(sb::solveIcpUpdate(wall, plain));
  CHECK(held == plain);
}

TEST_CASE("block sums: normal noise in front of a wall averages out, the structure of a corner stays",
          "[pipeline][quality]") {
  using Row = Eigen::Matrix<double, 6, 1>;
  // J^T J and the row count of Jacobian rows.
  const auto normalSums = [](const std::vector<Row>& rows) {
    sb::TrackSums s{};
    for (const Row& j : rows) {
      int k = 7;
      for (int a = 0; a < 6; ++a)
        for (int b = a; b < 6; ++b) s[size_t(k++)] += j(a) * j(b);
      s[28] += 1;
    }
    return s;
  };
  const Eigen::Vector3d c(2.5, 2.5, 1.5);
  for (const int planes : {1, 3}) {
    INFO(planes << " plane(s)");
    // Blocks as an image makes them: 16 neighbouring points of one plane (within 2 cm of a random centre from
    // scene()), each block counted once as the sum of its rows / sqrt(16), as ComputeBackend::blockSums does.
    const std::vector<Point> centres = scene(c, planes, 0.0);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-0.02, 0.02);
    std::normal_distribution<double> noise(0.0, 0.05);
    std::vector<Row> pixels, blocks;
    for (size_t b = 0; b < 600; ++b) {
      const Point& centre = centres[b];
      // Two directions in the plane.
      const Eigen::Vector3d e1 = centre.trueN.unitOrthogonal(), e2 = centre.trueN.cross(e1);
      Row sum = Row::Zero();
      for (int k = 0; k < 16; ++k) {
        const Eigen::Vector3d p = centre.p + u(rng) * e1 + u(rng) * e2;
        const Eigen::Vector3d n = (centre.trueN + Eigen::Vector3d(noise(rng), noise(rng), noise(rng))).normalized();
        Row j;
        j << n, p.cross(n);
        pixels.push_back(j);
        sum += j;
      }
      blocks.push_back(sum / 4.0);
    }
    const sb::TrackingQuality q = sb::trackingQuality(normalSums(pixels), normalSums(blocks), at(c), 0.0003);
    INFO("conditioning " << q.conditioning << ", per pixel " << q.icpConditioning);
    if (planes == 1) {
      CHECK(q.icpConditioning > 0.001);               // the noise floor of 0.05 rad normal noise
      CHECK(q.conditioning < q.icpConditioning / 8);  // falls by about the 16 rows of a block
      CHECK_FALSE(q.constrained);
    } else {
      CHECK(q.conditioning == Approx(q.icpConditioning).epsilon(0.1));
      CHECK(q.constrained);
    }
  }
}

TEST_CASE("twist log and exp are inverse", "[pipeline][quality]") {
  sb::Twist x;
  x << 0.3, -0.1, 0.05, 0.2, -0.4, 0.1;
  CHECK(sb::transformToTwist(sb::twistToTransform(x)).isApprox(x, 1e-12));
  x.tail<3>().setZero();
  CHECK(sb::transformToTwist(sb::twistToTransform(x)).isApprox(x, 1e-12));
}

TEST_CASE("a learnt motion follows the measurement along what the view fixes, not along what it leaves free",
          "[pipeline][quality]") {
  // Wall + floor seen from a camera far from the volume origin: sideways sliding (camera x) is free.
  const Eigen::Vector3d c(4.0, 1.0, 3.0);
  const sb::TrackingQuality two = quality(sums(scene(c, 2, 0.0)), at(c), 0.002);
  REQUIRE_FALSE(two.constrained);
  sb::Twist previous = sb::Twist::Zero(), measured = sb::Twist::Zero();
  previous(2) = 0.03;                // 3 cm/frame forward
  measured << 0.05, 0.0, 0.04, 0, 0, 0;  // a 5 cm slide sideways, 4 cm forward
  const sb::Twist learnt = sb::blendByStructure(two, previous, measured, 0.001);
  CHECK(learnt(0) == Approx(0.0).margin(1e-3));    // the slide is not learnt
  CHECK(learnt(2) == Approx(0.04).margin(1e-3));   // the constrained forward motion is
  // Three planes fix everything: the measurement is learnt (within lambda over the eigenvalues, > 0.05).
  const sb::TrackingQuality corner = quality(sums(scene(c, 3, 0.0)), at(c), 0.002);
  CHECK(sb::blendByStructure(corner, previous, measured, 0.001).isApprox(measured, 0.03));
  // lambda 0 or an unknown quality: the measurement.
  CHECK(sb::blendByStructure(two, previous, measured, 0.0) == measured);
  CHECK(sb::blendByStructure(sb::TrackingQuality{}, previous, measured, 0.001) == measured);
}

TEST_CASE("the twist log is exact near the identity", "[pipeline][quality]") {
  // 1 - cos(theta) cancels to 0 in doubles below about 1e-8 rad: a still camera must not give a NaN motion.
  for (double theta : {0.0, 1e-12, 1e-9, 1e-8, 1e-6, 1e-4, 1e-3, 2e-3}) {
    sb::Twist x;
    x << 0.01, -0.02, 0.03, theta, 0.0, 0.0;
    const sb::Twist back = sb::transformToTwist(sb::twistToTransform(x));
    REQUIRE(back.allFinite());
    CHECK((back - x).norm() < 1e-8);  // the rotation's angle is read back through acos: ~1e-8 rad resolution
  }
}
