// config/controller.json parses, selects adaptive, and its documented values are the built-in defaults.

#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>

#include "controller/adaptive_controller.h"
#include "controller/registry.h"
#include "controller/slambooster_controller.h"
#include "controller/step_controller.h"

TEST_CASE("config/controller.json holds the defaults", "[controller][config]") {
  std::ifstream in(SB_CONTROLLER_CONFIG);
  REQUIRE(in.good());
  const auto file = nlohmann::json::parse(in).at("controller");
  const sb::ControllerContext context;
  const auto settings = sb::parseControllerSettings(file, context, SB_CONTROLLER_CONFIG);
  CHECK(settings.name == "adaptive");
  // Every key of the file's slambooster section equals the default: parsing it on its own gives the same
  // controller decisions as parsing nothing.
  const sb::SlamBoosterConfig fromFile = sb::parseSlamBoosterConfig(file.at("slambooster"), "file");
  const sb::SlamBoosterConfig defaults = sb::parseSlamBoosterConfig(nlohmann::json::object(), "defaults");
  CHECK(fromFile.bootstrapFrames == defaults.bootstrapFrames);
  CHECK(fromFile.pid.vStand == defaults.pid.vStand);
  CHECK(fromFile.pid.vLow == defaults.pid.vLow);
  CHECK(fromFile.pid.integralThreshold == defaults.pid.integralThreshold);
  CHECK(fromFile.rate.approximationHoldFrames == defaults.rate.approximationHoldFrames);
  CHECK(fromFile.surface.stdThresholdM == defaults.surface.stdThresholdM);
  CHECK(fromFile.correction.velocityThreshold == defaults.correction.velocityThreshold);
  CHECK(fromFile.correction.maxExtrapolatedFrames == defaults.correction.maxExtrapolatedFrames);
  CHECK(fromFile.ladder.icpLevels == defaults.ladder.icpLevels);
  for (int l = 0; l <= 3; ++l) CHECK(fromFile.ladder.coupled(l) == defaults.ladder.coupled(l));
  CHECK(defaults.pid.vStand == 0.030);
  CHECK(defaults.pid.vLow == 0.004);
  CHECK(defaults.correction.velocityThreshold == 0.035);
  CHECK(defaults.surface.stdThresholdM == 0.14);
  const sb::AdaptiveConfig adaptive = sb::parseAdaptiveConfig(file.at("adaptive"), "file");
  const sb::AdaptiveConfig adaptiveDefaults = sb::parseAdaptiveConfig(nlohmann::json::object(), "defaults");
  CHECK(adaptive.initialLevel == adaptiveDefaults.initialLevel);
  CHECK(adaptive.bootstrapFrames == adaptiveDefaults.bootstrapFrames);
  CHECK(adaptive.retrackLevels == adaptiveDefaults.retrackLevels);
  CHECK(adaptive.holdFrames == adaptiveDefaults.holdFrames);
  CHECK(adaptive.relaxFrames == adaptiveDefaults.relaxFrames);
  CHECK(adaptive.maxExtrapolatedFrames == adaptiveDefaults.maxExtrapolatedFrames);
  CHECK(adaptive.predictStart == adaptiveDefaults.predictStart);
  CHECK(adaptive.integrateUnconstrained == adaptiveDefaults.integrateUnconstrained);
  CHECK(adaptive.icpHoldConditioning == adaptiveDefaults.icpHoldConditioning);
  CHECK(adaptive.learnConditioning == adaptiveDefaults.learnConditioning);
  CHECK(adaptive.poseConditioning == adaptiveDefaults.poseConditioning);
  CHECK(adaptive.confirmTranslationM == adaptiveDefaults.confirmTranslationM);
  CHECK(adaptive.confirmRotationDeg == adaptiveDefaults.confirmRotationDeg);
  CHECK(adaptive.evidence.maxUpdateNorm == adaptiveDefaults.evidence.maxUpdateNorm);
  CHECK(adaptive.evidence.inlierDropRatio == adaptiveDefaults.evidence.inlierDropRatio);
  CHECK(adaptive.evidence.inlierWindowFrames == adaptiveDefaults.evidence.inlierWindowFrames);
  CHECK(adaptive.evidence.predictionTranslationM == adaptiveDefaults.evidence.predictionTranslationM);
  CHECK(adaptive.evidence.predictionRotationDeg == adaptiveDefaults.evidence.predictionRotationDeg);
  CHECK(adaptive.evidence.weakConditioning == adaptiveDefaults.evidence.weakConditioning);
  CHECK(adaptive.integration.translationM == adaptiveDefaults.integration.translationM);
  CHECK(adaptive.integration.rotationDeg == adaptiveDefaults.integration.rotationDeg);
  CHECK(adaptive.integration.maxGapFrames == adaptiveDefaults.integration.maxGapFrames);
  for (int l = 0; l <= 3; ++l) CHECK(adaptive.ladder.coupled(l) == adaptiveDefaults.ladder.coupled(l));
  const sb::StepConfig step = sb::parseStepConfig(file.at("step"), "file");
  CHECK(step.icpMaxLevel == sb::parseStepConfig(nlohmann::json::object(), "d").icpMaxLevel);
}
