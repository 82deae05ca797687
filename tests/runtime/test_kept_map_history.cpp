// The path the wheels drove behind a kept map's candidate (runtime/kept_map_history.h; issue 55): which earlier
// views are kept, where each is put under a candidate, and the verdict on what ICP makes of them. ICP is a fake
// here (a TryView returning set attempts): the placement and the rule, not the tracking, are under test.

#include <catch2/catch.hpp>
#include <map>
#include <vector>

#include "runtime/kept_map_history.h"

namespace {

using sb::KeptMapHistory;

// A frame whose first pixel names it (the fake ICP tells the views apart by it).
sb::DepthFrame frameNamed(uint16_t name) {
  sb::DepthFrame f;
  f.depth = sb::DepthRaw(4, 3, 1000);
  f.depth(0, 0) = name;
  f.index = name;
  return f;
}

Eigen::Isometry3d forward(double metres) {
  Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
  step.translation().z() = metres;
  return step;
}

// An attempt as ICP would leave it: `agreement` of the pairs agreeing within the noise, `coverage` of the pixels
// paired, moved `movedM` from its start along x.
sb::TrackAttempt attempt(const Eigen::Isometry3d& start, double agreement, double coverage, double movedM = 0.0) {
  sb::TrackAttempt a;
  a.start = start;
  a.T_camera_to_world = start;
  a.T_camera_to_world.translation().x() += movedM;
  a.tracked = true;
  a.pairAgreement = 0.9;
  a.inlierFraction = coverage * a.pairAgreement;
  a.modelCoverage = coverage;
  a.agreementInNoise = agreement;
  return a;
}

// A robot driving straight along +z at 0.0625 m a frame (a view kept every fourth frame, 0.25 m) for `frames`
// frames, the wheels exact.
constexpr double kStepM = 0.0625;
KeptMapHistory drive(int frames) {
  KeptMapHistory h;
  for (int i = 0; i < frames; ++i)
    h.add(frameNamed(static_cast<uint16_t>(i + 1)), i == 0 ? std::optional<Eigen::Isometry3d>() : forward(kStepM));
  return h;
}

}  // namespace

TEST_CASE("the history keeps a view every 0.2 m of the wheels' path, the last ones, and starts again on a break",
          "[runtime][kept_map]") {
  KeptMapHistory h = drive(9);  // 0.5 m: views at 0, 0.25, 0.5 m
  CHECK(h.size() == 3);
  CHECK(h.pathM() == Approx(0.5));
  h = drive(400);  // 24.9 m: the last kMaxViews
  CHECK(h.size() == KeptMapHistory::kMaxViews);
  h.add(frameNamed(999), std::nullopt);  // no wheels' step: the path is broken
  CHECK(h.size() == 1);
  CHECK(h.pathM() == 0.0);
}

TEST_CASE("each earlier view is tried where the wheels put it under the candidate", "[runtime][kept_map]") {
  const KeptMapHistory h = drive(25);  // 1.5 m; the camera now at z = 1.5 in the wheels' chain
  // The candidate: the camera now, in the kept map's frame, turned 90 degrees about y and moved.
  Eigen::Isometry3d candidate = Eigen::Isometry3d::Identity();
  candidate.linear() = Eigen::AngleAxisd(0.5 * 3.141592653589793, Eigen::Vector3d::UnitY()).toRotationMatrix();
  candidate.translation() = Eigen::Vector3d(3.0, 0.0, -2.0);
  std::map<uint16_t, Eigen::Isometry3d> starts;
  const auto verdict = h.check(candidate, sb::PathTest{0.95, 0.03}, [&](const sb::DepthFrame& v, const Eigen::Isometry3d& s) {
    starts[v.depth(0, 0)] = s;
    return attempt(s, 0.99, 0.9);
  });
  // Views of frames 1, 5, 9, ... (z = 0, 0.25, ...), the one in hand (frame 25) not among them.
  REQUIRE(starts.size() == 6);
  CHECK(starts.count(25) == 0);
  for (const auto& [name, start] : starts) {
    const double back = 1.5 - kStepM * (name - 1);  // metres behind the camera now, along its view
    const Eigen::Isometry3d expected = candidate * forward(-back);
    INFO("frame " << name);
    CHECK((start.translation() - expected.translation()).norm() < 1e-9);
    CHECK(start.linear().isApprox(expected.linear()));
  }
  CHECK(verdict.views == 6);
  CHECK(verdict.covered == 6);
  CHECK(verdict.fit == 6);
  CHECK_FALSE(verdict.refused());
  CHECK(verdict.pathM == Approx(1.5));
}

TEST_CASE("a covered earlier view that does not fit in place refuses the candidate; an uncovered one says nothing",
          "[runtime][kept_map]") {
  const KeptMapHistory h = drive(25);
  const sb::PathTest test{0.95, 0.03};
  const Eigen::Isometry3d candidate = Eigen::Isometry3d::Identity();
  // Every view fits: accepted.
  auto fitsExcept = [&](uint16_t odd, double agreement, double coverage, double moved) {
    return h.check(candidate, test, [&](const sb::DepthFrame& v, const Eigen::Isometry3d& s) {
      return v.depth(0, 0) == odd ? attempt(s, agreement, coverage, moved) : attempt(s, 0.99, 0.9);
    });
  };
  CHECK_FALSE(fitsExcept(1, 0.99, 0.9, 0.0).refused());
  // The oldest view (1.5 m back) agreeing under the bar within the noise: another building.
  const auto wrong = fitsExcept(1, 0.90, 0.9, 0.0);
  CHECK(wrong.refused());
  CHECK(wrong.worstAgreement == Approx(0.90));
  CHECK(wrong.why.find("needed 0.950") != std::string::npos);
  // The same view, the kept surface covering under half of it (a place the store never saw): not judged, and the
  // path judged stops at the next one (1.25 m).
  const auto uncovered = fitsExcept(1, 0.50, 0.4, 0.0);
  CHECK_FALSE(uncovered.refused());
  CHECK(uncovered.covered == 5);
  CHECK(uncovered.pathM == Approx(1.25));
  // Agreeing, but ICP moved it farther than the wheels can be wrong over 1.5 m (0.05 + 3 x 0.03 x 1.5 = 0.185 m):
  // it fits somewhere else, not where the wheels put it.
  CHECK(fitsExcept(1, 0.99, 0.9, 0.20).refused());
  CHECK_FALSE(fitsExcept(1, 0.99, 0.9, 0.17).refused());
  // Nearer, the wheels' error is smaller: 0.14 m at 0.25 m back is not the wheels' (0.05 + 0.0225).
  CHECK(fitsExcept(21, 0.99, 0.9, 0.14).refused());
}
