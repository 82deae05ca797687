// The shipped config/pipeline.json parses and equals the built-in defaults, and lists every key, so
// documentation, file and code cannot drift apart. Its "odometry" section is the odometry module's
// (odometry/odometry_config.h), read beside the pipeline's keys as a run reads it (runtime/run_setup.h).

#include <catch2/catch.hpp>

#include "odometry/odometry_config.h"
#include "pipeline/config.h"
#include "runtime/run_setup.h"

TEST_CASE("config/pipeline.json equals the built-in defaults and lists every key", "[config]") {
  const sb::SettingsFile file = sb::readSettingsFile(SB_DEFAULT_CONFIG);
  const sb::PipelineConfig defaults;
  sb::PipelineConfig start = defaults;
  start.volumeResolution = 64;  // values the file must overwrite
  start.mu = 0.5f;
  const sb::PipelineConfig fromFile = sb::parseConfig(file.pipeline, start, SB_DEFAULT_CONFIG);
  CHECK(sb::configToJson(fromFile) == sb::configToJson(defaults));
  const nlohmann::json pipelineKeys = sb::configToJson(defaults);
  for (const auto& item : pipelineKeys.items()) {
    INFO(item.key());
    CHECK(file.pipeline.contains(item.key()));
  }

  REQUIRE(file.odometry.is_object());
  const sb::odometry::OdometryConfig odometryDefaults;
  CHECK(sb::odometry::odometryConfigFrom(file.odometry, SB_DEFAULT_CONFIG).toJson() == odometryDefaults.toJson());
  const nlohmann::json odometryKeys = odometryDefaults.toJson();
  for (const auto& item : odometryKeys.items()) {
    INFO("odometry." << item.key());
    CHECK(file.odometry.contains(item.key()));
  }
}
