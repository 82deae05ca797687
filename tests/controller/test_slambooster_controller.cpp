// The slambooster controller on scripted observation sequences: exact knob-level traces for the bootstrap,
// the rate limits, P, I, D, the surface trigger and pose correction.

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "controller/registry.h"
#include "controller/slambooster_controller.h"
#include "core/error.h"
#include "tests/controller/observation_script.h"

using sb::test::levelTrace;

namespace {

sb::SlamBoosterConfig config(const std::string& json) {
  return sb::readControllerSettings<sb::SlamBoosterConfig>(nlohmann::json::parse(json), "test");
}

std::vector<double> repeat(double v, size_t n) { return std::vector<double>(n, v); }

std::vector<double> concat(std::vector<double> a, const std::vector<double>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

}  // namespace

TEST_CASE("bootstrap, then approximation one level per hold, precision one level per frame", "[controller][slambooster]") {
  // PID only, with the I and D terms off: slow motion gives P = 3, then a fast burst gives P = 0.
  sb::SlamBoosterController c("pid", config(R"({"integral": false, "derivative": false, "surface_detection": false,
                                                 "pose_correction": false, "half_precision": false})"));
  CHECK(c.initialKnobs() == sb::parseKnobs("csr=1,icp=1e-5,pd=10:5:4,ir=1"));
  std::vector<uint32_t> triggers;
  const auto levels = levelTrace(c, concat(repeat(0.001, 23), repeat(0.030, 4)), &triggers);
  // Decisions 0..12 keep the bootstrap (frames 0..13 at level 0); the first controlled decision (after frame
  // 13) wants level 3 but is held 3 frames per step; the burst returns one level per frame.
  const std::vector<int> expected = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,  // bootstrap
                                     0, 0, 1, 1, 1, 2, 2, 2, 3, 3,           // hold 3 per step
                                     2, 1, 0, 0};                           // burst: one level per frame
  CHECK(levels == expected);
  for (size_t i = 0; i < 13; ++i) CHECK(triggers[i] == sb::kTriggerBootstrap);
  CHECK(triggers[13] == sb::kTriggerHold);
  CHECK(triggers[15] == 0);
  CHECK(triggers[16] == sb::kTriggerHold);

  // The coupled knobs of the final level and the level-3 knobs.
  sb::SlamBoosterController again("pid", config(R"({"integral": false, "derivative": false, "surface_detection": false,
                                                     "pose_correction": false})"));
  sb::test::ObservationScript script;
  sb::Decision d;
  for (int i = 0; i < 23; ++i) {
    const auto o = script.nextSpeed(0.001);
    d = again.decide(o);
    script.finish(o, d);
  }
  CHECK(d.level == 3);
  CHECK(d.next == sb::parseKnobs("csr=8,icp=1e-4,pd=4:5:4,ir=1"));
  CHECK(d.halfPrecision);  // half_precision defaults on outside the bootstrap
}

TEST_CASE("P maps velocity to a level between v_low and v_stand", "[controller][slambooster]") {
  const char* json = R"({"integral": false, "derivative": false, "surface_detection": false, "pose_correction": false,
                         "bootstrap_frames": 1, "approximation_hold_frames": 1, "approximation_step_levels": 3,
                         "precision_step_levels": 3})";
  // Kp = 3 / 0.026: 0.004 -> 3, 0.012 -> trunc(2.08) = 2, 0.020 -> trunc(1.15) = 1, 0.025 -> 0, 0.05 -> 0.
  const std::vector<std::pair<double, int>> cases = {{0.0, 3}, {0.004, 3}, {0.012, 2}, {0.020, 1}, {0.025, 0}, {0.05, 0}};
  for (const auto& [v, level] : cases) {
    INFO("velocity " << v);
    sb::SlamBoosterController c("pid", config(json));
    CHECK(levelTrace(c, repeat(v, 6)).back() == level);
  }
}

TEST_CASE("I: a window mean above the threshold costs one level", "[controller][slambooster]") {
  const char* json = R"({"derivative": false, "surface_detection": false, "pose_correction": false})";
  sb::SlamBoosterController fast("pid", config(json));
  std::vector<uint32_t> triggers;
  // 0.016 m/frame: P = trunc(115.4 * 0.014) = 1, the 10-frame mean 0.016 > 0.015 -> 0.
  const auto levels = levelTrace(fast, repeat(0.016, 30), &triggers);
  CHECK(levels.back() == 0);
  CHECK((triggers.back() & sb::kTriggerIntegral) != 0);
  sb::SlamBoosterController slower("pid", config(json));
  // 0.014 m/frame: P = trunc(1.84) = 1, mean below the threshold -> 1.
  CHECK(levelTrace(slower, repeat(0.014, 30)).back() == 1);
}

TEST_CASE("D: rising velocity costs a level, consistently falling velocity grants one", "[controller][slambooster]") {
  const char* json = R"({"integral": false, "surface_detection": false, "pose_correction": false,
                         "approximation_hold_frames": 1})";
  std::vector<double> rising, falling;
  for (int i = 0; i < 30; ++i) {
    rising.push_back(0.008 + 0.0001 * i);   // P = 2 throughout (0.0084 .. 0.0109)
    falling.push_back(0.0225 - 0.0001 * i);  // P = 0 at 0.0225 .. 0.0222, 1 from 0.0216 down (0.0196 at the end)
  }
  sb::SlamBoosterController up("pid", config(json));
  std::vector<uint32_t> upTriggers;
  CHECK(levelTrace(up, rising, &upTriggers).back() == 1);
  CHECK((upTriggers.back() & sb::kTriggerDerivativeUp) != 0);

  sb::SlamBoosterController down("pid", config(json));
  std::vector<uint32_t> downTriggers;
  CHECK(levelTrace(down, falling, &downTriggers).back() == 2);
  CHECK((downTriggers.back() & sb::kTriggerDerivativeDown) != 0);

  sb::SlamBoosterController original("pid", config(R"({"integral": false, "surface_detection": false,
      "pose_correction": false, "approximation_hold_frames": 1, "derivative_allows_approximation": false})"));
  CHECK(levelTrace(original, falling).back() == 1);
}

TEST_CASE("a smooth surface in view costs one level", "[controller][slambooster]") {
  sb::SlamBoosterController c("pid+surface", config(R"({"integral": false, "derivative": false, "pose_correction": false,
                                                       "bootstrap_frames": 1, "approximation_hold_frames": 1})"));
  const sb::DepthRaw wall(64, 48, 2000);  // 2 m everywhere (scale 1000): flat
  sb::DepthRaw textured(64, 48);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) textured(x, y) = static_cast<uint16_t>(1000 + (x * 37 + y * 91) % 2000);
  sb::test::ObservationScript script;
  std::vector<int> levels;
  for (int i = 0; i < 12; ++i) {
    sb::Observation o = script.nextSpeed(0.001);  // P = 3
    o.depth = i < 8 ? &textured : &wall;
    o.depthScale = 1000.0;
    const sb::Decision d = c.decide(o);
    script.finish(o, d);
    levels.push_back(d.level);
    CHECK(((d.triggers & sb::kTriggerSurface) != 0) == (i >= 8));
  }
  CHECK(levels == std::vector<int>{1, 2, 3, 3, 3, 3, 3, 3, 2, 2, 2, 2});
}

TEST_CASE("pose correction replaces a jump and a failed track by the extrapolated rigid motion", "[controller][slambooster]") {
  sb::SlamBoosterController c("pid+surface+correction", config(R"({"surface_detection": false})"));
  // A constant screw motion: 1 cm along x and 1 degree about y per frame.
  Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
  step.translate(Eigen::Vector3d(0.01, 0, 0.002));
  step.rotate(Eigen::AngleAxisd(M_PI / 180.0, Eigen::Vector3d::UnitY()));
  sb::test::ObservationScript script;
  Eigen::Isometry3d lastPose = Eigen::Isometry3d::Identity();
  int correctedCount = 0;
  for (int i = 0; i < 30; ++i) {
    Eigen::Isometry3d motion = i >= 4 ? step : Eigen::Isometry3d::Identity();
    const bool jump = i == 20;
    const bool lost = i == 25;
    if (jump) motion.translation() += Eigen::Vector3d(0.2, 0, 0);  // a 20 cm glitch
    const sb::Observation o = script.next(motion, !lost);
    const sb::Decision d = c.decide(o);
    script.finish(o, d);
    if (jump || lost) {
      INFO("frame " << i);
      REQUIRE(d.correctedPose);
      // Pose_t = T_{t-1} * Pose_{t-1}, T the world-frame motion of the last good frame (the script's `step`).
      const Eigen::Isometry3d expected = step * lastPose;
      CHECK(d.correctedPose->isApprox(expected, 1e-9));
      CHECK((d.triggers & sb::kTriggerCorrection) != 0);
      CHECK(d.level < 2);  // the trigger also asks for precision (P alone would allow 2)
      ++correctedCount;
    } else {
      INFO("frame " << i << " velocity " << o.velocity);
      CHECK_FALSE(d.correctedPose);
    }
    lastPose = d.correctedPose ? *d.correctedPose : o.pose;
  }
  CHECK(correctedCount == 2);

  // Without the part (the registry's `pid`), the jump stands.
  const sb::ControllerContext context;
  auto pid = sb::createController("pid", sb::parseControllerSettings(nlohmann::json("pid"), context), context);
  sb::test::ObservationScript plain;
  for (int i = 0; i < 22; ++i) {
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    if (i == 20) motion.translation().x() = 0.2;
    const auto o = plain.next(motion);
    const auto d = pid->decide(o);
    plain.finish(o, d);
    CHECK_FALSE(d.correctedPose);
  }
}

TEST_CASE("a correction does not feed the next: the frame after it is accepted when tracked", "[controller][slambooster]") {
  // The blank-wall stress sequence's runaway: a real fast frame (just above the jump threshold) is corrected to
  // the slower extrapolation; the tracker then follows the true camera, so each next frame's velocity against
  // the extrapolated pose exceeded the threshold too, and every frame was corrected from there on.
  sb::SlamBoosterController c("pid+surface+correction", config(R"({"surface_detection": false})"));
  Eigen::Isometry3d slow = Eigen::Isometry3d::Identity(), fast = Eigen::Isometry3d::Identity();
  slow.translation().x() = 0.007;
  fast.translation().x() = 0.036;
  Eigen::Isometry3d truth = Eigen::Isometry3d::Identity(), previousFinal = Eigen::Isometry3d::Identity();
  int corrected = 0;
  for (int i = 0; i < 40; ++i) {
    const Eigen::Isometry3d motion = i < 4 ? Eigen::Isometry3d::Identity() : (i == 20 ? fast : slow);
    truth = motion * truth;
    sb::Observation o;
    o.frame = i;
    o.previousPose = previousFinal;
    o.trackingAttempted = i >= 4;
    o.tracked = o.trackingAttempted;
    o.pose = o.tracked ? truth : previousFinal;  // the tracker finds the true camera
    o.velocity = (o.pose.translation() - o.previousPose.translation()).norm();
    const sb::Decision d = c.decide(o);
    INFO("frame " << i << " velocity " << o.velocity);
    CHECK(d.correctedPose.has_value() == (i == 20));
    if (d.correctedPose) {
      ++corrected;
      // Extrapolated with the last learnt motion, not the fast frame's.
      CHECK(d.correctedPose->translation().isApprox(slow * o.previousPose.translation(), 1e-12));
    }
    previousFinal = d.correctedPose ? *d.correctedPose : o.pose;
  }
  CHECK(corrected == 1);
  CHECK((previousFinal.translation() - truth.translation()).norm() < 1e-12);  // back on the true camera
}

TEST_CASE("a camera lost for long is extrapolated for a few frames, then held", "[controller][slambooster]") {
  sb::SlamBoosterController c("pid+surface+correction",
                              config(R"({"surface_detection": false, "correction_max_extrapolated_frames": 3})"));
  Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
  step.translation().x() = 0.01;
  sb::test::ObservationScript script;
  Eigen::Isometry3d lastGood = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 20; ++i) {
    const bool lost = i >= 10;
    const sb::Observation o = script.next(i >= 4 ? step : Eigen::Isometry3d::Identity(), !lost);
    const sb::Decision d = c.decide(o);
    script.finish(o, d);
    INFO("frame " << i);
    CHECK(d.correctedPose.has_value() == lost);
    if (!lost) lastGood = o.pose;
    if (lost) {
      const int extrapolated = std::min(i - 9, 3);  // frames 10, 11, 12 move on; then the pose holds
      Eigen::Isometry3d expected = lastGood;
      for (int k = 0; k < extrapolated; ++k) expected = step * expected;
      CHECK(d.correctedPose->isApprox(expected, 1e-9));
    }
  }
}

TEST_CASE("corrected poses stay rigid over many corrections", "[controller][slambooster]") {
  // A step run on synth-livingroom-traj0 wrote a quaternion of norm 0.9987 at frame 795: each correction
  // learnt its motion as Pose * Pose_prev^-1 with an inverse that assumes an orthonormal rotation, so the
  // rounding error of the rotation grew about threefold per correction (1e-14 at frame 35, 3e-5 by 608).
  sb::SlamBoosterController c("pid+surface+correction", config(R"({"surface_detection": false})"));
  Eigen::Isometry3d slow = Eigen::Isometry3d::Identity();
  slow.translate(Eigen::Vector3d(0.004, 0.001, 0.002));
  slow.rotate(Eigen::AngleAxisd(0.7 * M_PI / 180.0, Eigen::Vector3d(0.3, 1.0, 0.2).normalized()));
  Eigen::Isometry3d glitch = slow;
  glitch.translation() += Eigen::Vector3d(0.05, 0, 0);
  Eigen::Isometry3d previousFinal = Eigen::Isometry3d::Identity();
  double worst = 0;
  int corrected = 0;
  for (int i = 0; i < 400; ++i) {
    sb::Observation o;
    o.frame = i;
    o.previousPose = previousFinal;
    o.trackingAttempted = i >= 4;
    o.tracked = o.trackingAttempted;
    // Every fourth frame jumps; the tracker composes its motion onto the last final pose.
    const Eigen::Isometry3d& motion = i < 4 ? Eigen::Isometry3d::Identity() : (i % 4 == 3 ? glitch : slow);
    o.pose = o.tracked ? motion * previousFinal : previousFinal;
    o.velocity = (o.pose.translation() - o.previousPose.translation()).norm();
    const sb::Decision d = c.decide(o);
    previousFinal = d.correctedPose ? *d.correctedPose : o.pose;
    corrected += d.correctedPose ? 1 : 0;
    const Eigen::Matrix3d r = previousFinal.linear();
    worst = std::max(worst, (r.transpose() * r - Eigen::Matrix3d::Identity()).norm());
  }
  CHECK(corrected == 99);
  CHECK(worst < 1e-12);
}

TEST_CASE("the registry's slambooster variants switch the parts", "[controller][slambooster]") {
  const sb::ControllerContext context;
  const auto settings = sb::parseControllerSettings(
      nlohmann::json::parse(R"({"name": "slambooster", "slambooster": {"bootstrap_frames": 2}})"), context);
  const sb::DepthRaw wall(64, 48, 2000);
  for (const std::string name : {"pid", "pid+surface", "pid+surface+correction", "slambooster"}) {
    INFO(name);
    auto c = sb::createController(name, settings, context);
    sb::test::ObservationScript script;
    sb::Decision d;
    for (int i = 0; i < 6; ++i) {
      sb::Observation o = script.nextSpeed(0.001);
      o.depth = &wall;
      o.depthScale = 1000;
      if (i == 5) o.tracked = false;
      d = c->decide(o);
      script.finish(o, d);
    }
    CHECK(((d.triggers & sb::kTriggerSurface) != 0) == (name != "pid"));
    CHECK(d.correctedPose.has_value() == (name == "pid+surface+correction" || name == "slambooster"));
    CHECK(d.halfPrecision == (name == "slambooster"));
  }
  CHECK_THROWS_WITH(config(R"({"v_stand_m_per_frame": 0.001})"), Catch::Matchers::Contains("v_stand_m_per_frame"));
  CHECK_THROWS_WITH(config(R"({"surface_std_threshold_m": "low"})"), Catch::Matchers::Contains("surface_std_threshold_m"));
}
