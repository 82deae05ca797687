// The sensor model: noise statistics against the analytic disparity model, quantisation, range limits,
// grazing-angle and edge dropouts, determinism.

#include <catch2/catch.hpp>
#include <cmath>
#include <set>

#include "synth/renderer.h"
#include "synth/synth_sequence.h"

using namespace sb;
using namespace sb::synth;

namespace {

Scene planeScene(double distanceM, const Eigen::Vector3f& normal = {0.f, 0.f, -1.f}) {
  Scene s;
  s.name = "test";
  s.primitives.push_back(makePlane({0.f, 0.f, static_cast<float>(distanceM)}, normal));
  return s;
}

DepthMeters renderWith(const Scene& scene, const SensorModel& model, uint64_t seed) {
  const Renderer renderer(scene, iclNuimIntrinsics());
  DepthMeters depth;
  renderer.render(Eigen::Isometry3d::Identity(), model, seed, depth);
  return depth;
}

struct Stats {
  double mean = 0, std = 0;
  size_t valid = 0;
};

Stats statsOf(const DepthMeters& d) {
  Stats s;
  double sum = 0, sum2 = 0;
  for (float v : d.pixels()) {
    if (v <= 0.f) continue;
    sum += v, sum2 += double(v) * v, ++s.valid;
  }
  s.mean = sum / s.valid;
  s.std = std::sqrt(sum2 / s.valid - s.mean * s.mean);
  return s;
}

}  // namespace

TEST_CASE("depth noise on a flat wall matches sigma_z = z^2 sigma_d / (b f) plus quantisation", "[synth][noise]") {
  const double fx = iclNuimIntrinsics().fx;
  for (const auto& [z, sigmaD] : std::vector<std::pair<double, double>>{{2.0, 0.2}, {1.0, 0.5}, {3.0, 0.5}}) {
    CAPTURE(z, sigmaD);
    SensorModel model;
    model.sigmaDisparityPx = sigmaD;
    const DepthMeters depth = renderWith(planeScene(z), model, 11);
    const Stats s = statsOf(depth);
    REQUIRE(s.valid == depth.size());  // a fronto-parallel wall in range: no dropouts
    const double sigmaZ = model.sigmaDepthM(z, fx);
    const double stepZ = z * z / (model.baselineM * fx) * model.disparityStepPx;
    const double expected = std::sqrt(sigmaZ * sigmaZ + stepZ * stepZ / 12.0);  // quantisation adds step^2/12
    REQUIRE(s.std == Approx(expected).epsilon(0.05));
    REQUIRE(s.mean == Approx(z).margin(0.1 * sigmaZ + 1e-3));
  }
}

TEST_CASE("measured disparities lie on the quantisation grid", "[synth][noise]") {
  SensorModel model;
  model.sigmaDisparityPx = 0.2;  // wide enough to cover many steps
  const double bf = model.baselineM * iclNuimIntrinsics().fx;
  const DepthMeters depth = renderWith(planeScene(2.0), model, 3);
  std::set<float> distinct;
  for (float z : depth.pixels()) {
    REQUIRE(z > 0.f);
    const double steps = bf / z / model.disparityStepPx;
    REQUIRE(std::abs(steps - std::round(steps)) < 1e-3);
    distinct.insert(z);
  }
  // sigma_d = 0.2 px spans a few tens of 1/8-px steps, not thousands of distinct depths.
  REQUIRE(distinct.size() >= 5);
  REQUIRE(distinct.size() < 40);

  model.disparityStepPx = 0.0;  // without quantisation nearly every pixel differs
  const DepthMeters smooth = renderWith(planeScene(2.0), model, 3);
  REQUIRE(std::set<float>(smooth.pixels().begin(), smooth.pixels().end()).size() > 10000);
}

TEST_CASE("depth outside the sensor range reads as missing", "[synth][noise]") {
  for (bool noise : {false, true}) {
    CAPTURE(noise);
    SensorModel model;
    model.noise = noise;
    REQUIRE(statsOf(renderWith(planeScene(5.0), model, 1)).valid == 0);
    REQUIRE(statsOf(renderWith(planeScene(0.3), model, 1)).valid == 0);
    model.maxDepthM = 6.0;
    REQUIRE(statsOf(renderWith(planeScene(5.0), model, 1)).valid > 0);
  }
  SensorModel exact;
  exact.noise = false;
  REQUIRE(statsOf(renderWith(planeScene(4.4), exact, 1)).valid == size_t{640} * 480);
}

TEST_CASE("grazing surfaces and depth edges lose their readings when noise is on", "[synth][noise]") {
  SensorModel noisy;
  SensorModel exact;
  exact.noise = false;
  SECTION("grazing") {
    // Normal 80 degrees from the optical axis: beyond maxIncidenceDeg (75) near the image centre.
    const Eigen::Vector3f steep(std::sin(1.396f), 0.f, -std::cos(1.396f));
    const Scene scene = planeScene(2.0, steep);
    const DepthMeters withNoise = renderWith(scene, noisy, 1), without = renderWith(scene, exact, 1);
    REQUIRE(withNoise(320, 240) == 0.f);
    REQUIRE(without(320, 240) == Approx(2.0).epsilon(0.01));  // 2 m on the axis; half a pixel off it
    // 30 degrees: readings stay.
    const Eigen::Vector3f mild(std::sin(0.5236f), 0.f, -std::cos(0.5236f));
    REQUIRE(renderWith(planeScene(2.0, mild), noisy, 1)(320, 240) > 0.f);
  }
  SECTION("edges") {
    Scene scene = planeScene(3.0);
    scene.primitives.push_back(makeBox({0.f, 0.f, 1.5f}, {0.6f, 0.6f, 0.2f}));  // spans x in [-0.3, 0.3] m
    // The box's right edge at x = 0.3 m, z = 1.4 m projects to column 319.5 + 481.2 * 0.3 / 1.4 = 422.6.
    const DepthMeters withNoise = renderWith(scene, noisy, 1), without = renderWith(scene, exact, 1);
    for (int x : {422, 423}) {
      REQUIRE(without(x, 240) > 0.f);
      REQUIRE(withNoise(x, 240) == 0.f);
    }
    REQUIRE(withNoise(400, 240) > 0.f);  // inside the box face
    REQUIRE(withNoise(450, 240) > 0.f);  // the wall behind
  }
}

TEST_CASE("noise is a function of the seed only", "[synth][noise]") {
  SensorModel model;
  const Scene scene = planeScene(2.5);
  const DepthMeters a = renderWith(scene, model, frameSeed(5, 10));
  REQUIRE(renderWith(scene, model, frameSeed(5, 10)).pixels() == a.pixels());
  REQUIRE(renderWith(scene, model, frameSeed(5, 11)).pixels() != a.pixels());
  REQUIRE(renderWith(scene, model, frameSeed(6, 10)).pixels() != a.pixels());
  REQUIRE(frameSeed(5, 10) != frameSeed(10, 5));
}
