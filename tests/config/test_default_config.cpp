// The shipped config/pipeline.json parses and equals the built-in defaults, and lists every key, so
// documentation, file and code cannot drift apart.

#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>

#include "pipeline/config.h"

TEST_CASE("config/pipeline.json equals the built-in defaults and lists every key", "[config]") {
  const sb::PipelineConfig defaults;
  sb::PipelineConfig start = defaults;
  start.volumeResolution = 64;  // values the file must overwrite
  start.mu = 0.5f;
  const sb::PipelineConfig fromFile = sb::loadConfigFile(SB_DEFAULT_CONFIG, start);
  CHECK(sb::configToJson(fromFile) == sb::configToJson(defaults));

  std::ifstream in(SB_DEFAULT_CONFIG);
  const auto file = nlohmann::json::parse(in);
  const nlohmann::json expected = sb::configToJson(defaults);
  for (const auto& item : expected.items()) {
    INFO(item.key());
    CHECK(file.contains(item.key()));
  }
}
