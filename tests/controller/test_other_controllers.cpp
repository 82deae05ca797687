// step, budget, tc and offline on scripted observations: exact knob traces and the selection rules.

#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>

#include "controller/budget_controller.h"
#include "controller/offline_controller.h"
#include "controller/step_controller.h"
#include "controller/tc_controller.h"
#include "controller/registry.h"
#include "core/error.h"
#include "tests/controller/observation_script.h"
#include "tests/support/test_data.h"

using sb::test::levelTrace;

namespace {

std::unique_ptr<sb::Controller> offline(const nlohmann::json& section) {
  return sb::createOfflineController("offline", sb::readControllerSettings<sb::OfflineSettings>(section, "test"), {},
                                     "test");
}

}  // namespace

TEST_CASE("step moves one knob one level per signal in the order csr, icp, pd0", "[controller][step]") {
  sb::StepController c("step", sb::readControllerSettings<sb::StepConfig>(nlohmann::json::parse(R"({"integral": false, "derivative": false,
      "surface_detection": false, "pose_correction": false, "bootstrap_frames": 1, "approximation_hold_frames": 1})"),
                                                   "test"));
  REQUIRE(c.positions() == 9);  // 3 csr + 2 icp (1e-5 -> 1e-3) + 3 pd0 levels
  const std::vector<std::string> knobs = {"csr=1,icp=1e-5,pd=10:5:4", "csr=2,icp=1e-5,pd=10:5:4", "csr=4,icp=1e-5,pd=10:5:4",
                                          "csr=8,icp=1e-5,pd=10:5:4", "csr=8,icp=1e-4,pd=10:5:4", "csr=8,icp=1e-3,pd=10:5:4",
                                          "csr=8,icp=1e-3,pd=8:5:4",  "csr=8,icp=1e-3,pd=6:5:4",  "csr=8,icp=1e-3,pd=4:5:4"};
  for (int p = 0; p < 9; ++p) CHECK(c.knobsAt(p) == sb::parseKnobs(knobs[size_t(p)] + ",ir=1"));
  // Slow: one step per frame up to the last position; then fast: one step back per frame.
  std::vector<double> speeds(12, 0.001);
  speeds.insert(speeds.end(), 4, 0.03);
  const auto levels = levelTrace(c, speeds);
  CHECK(levels == std::vector<int>{1, 2, 3, 4, 5, 6, 7, 8, 8, 8, 8, 8, 7, 6, 5, 4});
  // Target 1 (between the two thresholds) holds the position.
  sb::StepController hold("step", sb::readControllerSettings<sb::StepConfig>(nlohmann::json::parse(R"({"integral": false, "derivative": false,
      "surface_detection": false, "bootstrap_frames": 1, "approximation_hold_frames": 1})"), "test"));
  // Frames 0-3 are untracked (velocity 0, target 3): one step each; from frame 4 on P = 1: the position holds.
  CHECK(levelTrace(hold, std::vector<double>(8, 0.020)) == std::vector<int>{1, 2, 3, 4, 4, 4, 4, 4});
}

TEST_CASE("budget settles on the least approximation that meets the target time", "[controller][budget]") {
  sb::BudgetController c("budget", sb::readControllerSettings<sb::BudgetConfig>(nlohmann::json::parse(R"({"target_frame_ms": 30,
      "surface_detection": false, "pose_correction": false})"), "test"));
  // Cost of a frame at level L: 100 / 2^L ms -> level 2 (25 ms) is the least that fits 30 ms.
  sb::test::ObservationScript script;
  int level = 0;
  std::vector<int> levels;
  for (int i = 0; i < 80; ++i) {
    sb::Observation o = script.nextSpeed(0.005);
    o.previousComputationMs = i == 0 ? 0.0 : 100.0 / (1 << level);
    const sb::Decision d = c.decide(o);
    script.finish(o, d);
    level = d.level;
    levels.push_back(level);
  }
  for (int i = 0; i < 13; ++i) CHECK(levels[size_t(i)] == 0);  // bootstrap
  for (int i = 60; i < 80; ++i) CHECK(levels[size_t(i)] == 2);
  CHECK(c.estimate(0) == Approx(100.0));
  CHECK(c.estimate(2) == Approx(25.0));
  CHECK_THROWS_WITH(sb::readControllerSettings<sb::BudgetConfig>(nlohmann::json::object(), "cfg: controller.budget"),
                    Catch::Matchers::Contains("cfg: controller.budget") && Catch::Matchers::Contains("target_frame_ms"));
}

TEST_CASE("tc runs the fastest table entry whose velocity-scaled ATE fits the budget, per window", "[controller][tc]") {
  const auto table = nlohmann::json::parse(R"({"reference_ms_per_frame": 100, "entries": [
      {"knobs": "csr=1", "ms_per_frame": 100, "speedup": 1, "ate_m": 0.01},
      {"knobs": "csr=2", "ms_per_frame": 50, "speedup": 2, "ate_m": 0.02},
      {"knobs": "csr=4", "ms_per_frame": 25, "speedup": 4, "ate_m": 0.04}]})");
  nlohmann::json section = {{"inline_table", table}, {"window_frames", 4}, {"reference_velocity_m_per_frame", 0.01},
                            {"error_budget_m", 0.05}};
  sb::TcController c("tc", sb::readControllerSettings<sb::TcConfig>(section, "test"));
  CHECK(c.initialKnobs().csr == 1);
  CHECK(c.select(0.01) == 2);   // 0.04 * 1 <= 0.05
  CHECK(c.select(0.02) == 1);   // 0.04 * 2 > 0.05, 0.02 * 2 <= 0.05
  CHECK(c.select(0.06) == 0);   // nothing fits: the most accurate entry
  // Windows of 4 frames: the choice changes only at window ends.
  std::vector<double> speeds(8, 0.0);  // frames 0-3 untracked (velocity 0), 4-7 at 0.02 m/frame
  for (int i = 4; i < 8; ++i) speeds[size_t(i)] = 0.02;
  CHECK(levelTrace(c, speeds) == std::vector<int>{0, 0, 0, 2, 2, 2, 2, 1});

  std::vector<sb::TcEntry> candidates;
  for (auto [s, e] : std::vector<std::pair<double, double>>{{1, 0.01}, {2, 0.02}, {1.5, 0.03}, {4, 0.04}, {3, 0.05}}) {
    sb::TcEntry entry;
    entry.speedup = s;
    entry.ateM = e;
    candidates.push_back(entry);
  }
  const auto front = sb::paretoFront(candidates);
  REQUIRE(front.size() == 3);
  CHECK(front[0].speedup == 1);
  CHECK(front[1].speedup == 2);
  CHECK(front[2].speedup == 4);
  CHECK_THROWS_WITH(sb::readControllerSettings<sb::TcConfig>(nlohmann::json::object(), "w"), Catch::Matchers::Contains("'table' is required"));
}

TEST_CASE("offline replays the best knobs of a dse result", "[controller][offline]") {
  const std::string dir = sb::test::scratchDir("controller_offline");
  std::ofstream(dir + "/best.json") << R"({"best": {"knobs": "csr=4,icp=1e-4,pd=6:5:4,tr=1,ir=1", "ate_m": 0.03}})";
  auto c = offline({{"result", dir + "/best.json"}});
  CHECK(c->name() == "offline");
  CHECK(c->initialKnobs() == sb::parseKnobs("csr=4,icp=1e-4,pd=6:5:4,ir=1"));
  CHECK(c->decide(sb::Observation{}).next == c->initialKnobs());
  CHECK_THROWS_WITH(offline({{"result", dir + "/none.json"}}),
                    Catch::Matchers::Contains("none.json"));
  std::ofstream(dir + "/empty.json") << R"({"best": null})";
  CHECK_THROWS_WITH(offline({{"result", dir + "/empty.json"}}),
                    Catch::Matchers::Contains("no setting under the ATE bound"));
}
