// The registry: controllers by name from a validated config section; the fixed controller and its presets.

#include <catch2/catch.hpp>

#include "controller/registry.h"
#include "core/error.h"

using Catch::Matchers::Contains;

namespace {

const sb::ControllerContext kContext{sb::parseKnobs("csr=2")};

std::unique_ptr<sb::Controller> create(const std::string& json) {
  const auto settings = sb::parseControllerSettings(nlohmann::json::parse(json), kContext, "test.json: controller");
  return sb::createController(settings, kContext);
}

}  // namespace

TEST_CASE("fixed controllers return their knobs every frame", "[controller][fixed]") {
  auto def = create(R"("default")");
  CHECK(def->name() == "default");
  CHECK(def->initialKnobs() == sb::knobPreset("default"));
  auto acc = create(R"({"name": "accurate"})");
  CHECK(acc->initialKnobs() == sb::knobPreset("accurate"));

  // Without a preset, fixed runs the pipeline config's knobs (the context), with a knob string on top.
  auto base = create(R"("fixed")");
  CHECK(base->initialKnobs() == sb::parseKnobs("csr=2"));
  auto fixed = create(R"({"name": "fixed", "fixed": {"preset": "accurate", "knobs": "csr=4,pd=6:5:4", "half": true}})");
  const sb::Knobs expected = sb::parseKnobs("csr=4,pd=6:5:4", sb::knobPreset("accurate"));
  CHECK(fixed->initialKnobs() == expected);
  sb::Observation obs;
  for (size_t i = 0; i < 5; ++i) {
    obs.frame = i;
    obs.velocity = 0.1 * i;  // fixed ignores everything it observes
    const sb::Decision d = fixed->decide(obs);
    CHECK(d.next == expected);
    CHECK(d.halfPrecision);
    CHECK_FALSE(d.correctedPose);
    CHECK(d.triggers == 0);
  }
}

TEST_CASE("controller config errors name the key and what is allowed", "[controller][registry]") {
  CHECK_THROWS_WITH(create(R"("fastest")"), Contains("unknown controller 'fastest'") && Contains("fixed"));
  CHECK_THROWS_WITH(create(R"({"name": "fixed", "fixd": {}})"),
                    Contains("test.json: controller") && Contains("unknown key 'fixd'"));
  CHECK_THROWS_WITH(create(R"({"name": "fixed", "fixed": {"preset": "fast"}})"),
                    Contains("controller.fixed: 'preset'") && Contains("accurate"));
  CHECK_THROWS_WITH(create(R"({"name": "fixed", "fixed": {"knobs": "csr=3"}})"),
                    Contains("'knobs'") && Contains("csr=3"));
  CHECK_THROWS_WITH(create(R"({"name": "fixed", "fixed": {"half": 1}})"), Contains("'half' = 1") && Contains("expected true or false"));
  CHECK_THROWS_WITH(create(R"({"name": 3})"), Contains("'name'"));
  CHECK_THROWS_AS(create("[1, 2]"), sb::Error);
  // A bad section is refused even when another controller is selected (a later switch must not fail).
  CHECK_THROWS_WITH(create(R"({"name": "default", "fixed": {"extra": 1}})"), Contains("unknown key 'extra'"));
}

TEST_CASE("every registered name creates a controller with valid initial knobs", "[controller][registry]") {
  const auto names = sb::controllerNames();
  for (const char* required : {"fixed", "default", "accurate", "slambooster", "pid", "pid+surface",
                               "pid+surface+correction", "step", "tc", "offline", "budget"})
    CHECK(std::find(names.begin(), names.end(), required) != names.end());
  // The controllers that need parameters get them; every other one runs on its defaults.
  const auto settings = sb::parseControllerSettings(nlohmann::json::parse(R"({"name": "fixed",
      "budget": {"target_frame_ms": 30},
      "offline": {"knobs": "csr=2,icp=1e-4"},
      "tc": {"inline_table": {"reference_ms_per_frame": 100,
                              "entries": [{"knobs": "csr=1", "ms_per_frame": 100, "speedup": 1, "ate_m": 0.01}]}}})"),
                                                    kContext);
  for (const std::string& name : names) {
    INFO(name);
    auto c = sb::createController(name, settings, kContext);
    CHECK(c->name() == name);
    CHECK_NOTHROW(sb::validateKnobs(c->initialKnobs()));
  }
}
