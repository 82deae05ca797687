#include "controller/offline_controller.h"

#include <fstream>
#include <nlohmann/json.hpp>

#include "controller/fixed_controller.h"
#include "core/config_reader.h"
#include "core/error.h"
#include "core/input_file.h"

namespace sb {

Knobs loadDseBestKnobs(const std::string& path) {
  const std::string problem = pathProblem(path);
  if (!problem.empty())
    throw Error("dse result " + quoteForMessage(path) + " " + problem +
                " (run `slambooster dse SEQ --out DIR` first)");
  try {
    const nlohmann::json j = readJsonConfig(path, "dse result");  // the one settings-file loader
    const nlohmann::json& best = j.contains("best") ? j.at("best") : j;
    if (best.is_null()) throw Error("dse result '" + path + "' has no setting under the ATE bound");
    return parseKnobs(best.at("knobs").get<std::string>());
  } catch (const nlohmann::json::exception& e) {
    throw Error("dse result '" + path + "' is not a `slambooster dse` best.json: " + e.what());
  } catch (const Error& e) {
    throw Error("dse result '" + path + "': " + e.what());
  }
}

void OfflineSettings::read(ConfigReader& r) {
  r.string("result", result);
  r.string("knobs", knobs);
  r.finish();
  if (result.empty() == knobs.empty())
    throw Error(r.where() + ": set exactly one of 'result' (a `slambooster dse` best.json) and 'knobs'");
}

nlohmann::json OfflineSettings::toJson() const {
  return {{"result", result}, {"knobs", knobs}};
}

std::unique_ptr<Controller> createOfflineController(const std::string& name, const OfflineSettings& settings,
                                                    const ControllerContext&, const std::string& where) {
  FixedConfig c;
  try {
    c.knobs = settings.result.empty() ? parseKnobs(settings.knobs) : loadDseBestKnobs(settings.result);
  } catch (const Error& e) {
    throw Error(where + ": '" + (settings.result.empty() ? "knobs" : "result") + "': " + e.what());
  }
  return std::make_unique<FixedController>(name, c);
}

}  // namespace sb
