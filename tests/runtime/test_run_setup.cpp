// runtime/run_setup.h: the one setup of a run for both front ends: a settings file splits into pipeline keys
// and a controller section, the sequence's hints come before the file, and the front end's controller name
// wins or yields as it asks.

#include <catch2/catch.hpp>
#include <fstream>
#include <string>

#include "core/error.h"
#include "runtime/run_setup.h"
#include "tests/support/test_data.h"

using Catch::Matchers::Contains;

TEST_CASE("run setup: a settings file is pipeline keys and a controller section", "[runtime][setup]") {
  const std::string dir = sb::test::scratchDir("run_setup");
  std::ofstream(dir + "/both.json") << R"({"volume_resolution": 64, "controller": {"name": "step"}})";
  const sb::SettingsFile file = sb::readSettingsFile(dir + "/both.json");
  CHECK(file.pipeline == nlohmann::json{{"volume_resolution", 64}});
  CHECK(file.controller == nlohmann::json{{"name", "step"}});
  std::ofstream(dir + "/array.json") << "[1]";
  CHECK_THROWS_WITH(sb::readSettingsFile(dir + "/array.json"), Contains("array.json") && Contains("object"));
}

TEST_CASE("run setup: the sequence's hints, then the file; automatic becomes moving", "[runtime][setup]") {
  sb::SequenceInfo info;
  info.volumeSize = 6.0;
  info.volumeInitialPosition = std::array<double, 3>{0.5, 0.5, 0.1};
  sb::PipelineConfig c = sb::pipelineConfigFor(info, {{"volume_size_m", 3.0}}, "f.json");
  CHECK(c.volumeSize == 3.0f);                 // the file wins over the hint
  CHECK(c.initialPosition[2] == Approx(0.1));  // the hint wins over the default
  sb::finishPipelineConfig(c, "f.json");
  CHECK(c.volumeMode == sb::VolumeMode::moving);
  c.volumeResolution = 3;
  CHECK_THROWS_WITH(sb::finishPipelineConfig(c, "run options"), Contains("run options: "));
}

TEST_CASE("run setup: a moving volume keeps its own side, a fixed one takes the hint's",
          "[runtime][setup]") {
  // A corridor drive's hints: a 20.5 m cube holding the whole path. Taken by a moving volume they spread its 256
  // voxels 8 cm apart, and tracking drifted (docs/moving-volume.md "The sequence's hints").
  sb::SequenceInfo info;
  info.volumeSize = 20.5;
  info.volumeInitialPosition = std::array<double, 3>{0.52, 0.53, 0.09};
  const sb::PipelineConfig defaults;
  sb::PipelineConfig moving = sb::pipelineConfigFor(info, nlohmann::json::object(), "f.json");
  sb::finishPipelineConfig(moving, "f.json");
  CHECK(moving.volumeMode == sb::VolumeMode::moving);
  CHECK(moving.volumeSize == defaults.volumeSize);
  CHECK(moving.initialPosition[2] == Approx(0.09));  // the first position is the hint's (fractions of the side)

  sb::PipelineConfig fixed = sb::pipelineConfigFor(info, {{"volume_mode", "fixed"}}, "f.json");
  sb::finishPipelineConfig(fixed, "f.json");
  CHECK(fixed.volumeSize == 20.5f);
  CHECK(fixed.initialPosition[2] == Approx(0.09));

  // What a file (or a flag, which clears the mark) says stands, moving or not.
  sb::PipelineConfig chosen =
      sb::pipelineConfigFor(info, {{"volume_size_m", 8.0}, {"initial_position", {0.5, 0.5, 0.2}}}, "f.json");
  sb::finishPipelineConfig(chosen, "f.json");
  CHECK(chosen.volumeSize == 8.0f);
  CHECK(chosen.initialPosition[2] == Approx(0.2));
  sb::PipelineConfig flagged = sb::pipelineConfigFor(info, nlohmann::json::object(), "f.json");
  flagged.volumeSize = 12.0f;
  flagged.volumeHinted.size = false;
  sb::finishPipelineConfig(flagged, "run options");
  CHECK(flagged.volumeSize == 12.0f);
}

TEST_CASE("run setup: the front end's controller name wins or yields", "[runtime][setup]") {
  const sb::ControllerContext context{};
  const nlohmann::json section = {{"name", "step"}};
  // `run --controller` wins over the file's name; the daemon's slam.controller yields to its file's name.
  CHECK(sb::controllerSettingsFrom(section, "accurate", true, context, "f").name == "accurate");
  CHECK(sb::controllerSettingsFrom(section, "accurate", false, context, "f").name == "step");
  CHECK(sb::controllerSettingsFrom(nlohmann::json::object(), "accurate", false, context, "f").name ==
        "accurate");
  CHECK(sb::controllerSettingsFrom("step", "accurate", true, context, "f").name == "accurate");
  CHECK(sb::controllerSettingsFrom(nullptr, "", true, context, "f").name == "fixed");
  CHECK_THROWS_WITH(sb::controllerSettingsFrom(nullptr, "nosuch", true, context, "--controller"),
                    Contains("--controller") && Contains("nosuch"));
}
