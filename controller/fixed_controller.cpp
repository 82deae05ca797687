#include "controller/fixed_controller.h"

#include <nlohmann/json.hpp>

#include "core/config_reader.h"
#include "core/error.h"

namespace sb {

Decision FixedController::decide(const Observation&) {
  Decision d;
  d.next = config_.knobs;
  d.halfPrecision = config_.half;
  return d;
}

FixedConfig parseFixedConfig(const nlohmann::json& section, const std::string& where, const Knobs& base,
                             const std::string& preset) {
  ConfigReader r(section, where);
  FixedConfig c;
  std::string presetName = preset;
  std::string knobText;
  r.string("preset", presetName, {"default", "accurate"});
  r.string("knobs", knobText);
  r.boolean("half", c.half);
  r.finish();
  c.knobs = presetName.empty() ? base : knobPreset(presetName);
  try {
    c.knobs = parseKnobs(knobText, c.knobs);
  } catch (const Error& e) {
    throw Error(r.at("knobs") + ": " + e.what());
  }
  return c;
}

}  // namespace sb
