#include "controller/fixed_controller.h"

#include <nlohmann/json.hpp>

#include "core/error.h"

namespace sb {

Decision FixedController::decide(const Observation&) {
  Decision d;
  d.next = config_.knobs;
  d.halfPrecision = config_.half;
  return d;
}

void FixedSettings::read(ConfigReader& r) {
  r.string("preset", preset, {"default", "accurate"});
  r.string("knobs", knobs);
  r.boolean("half", half);
}

nlohmann::json FixedSettings::toJson() const {
  return {{"preset", preset}, {"knobs", knobs}, {"half", half}};
}

std::unique_ptr<Controller> createFixedController(const std::string& name, const FixedSettings& settings,
                                                  const ControllerContext& context,
                                                  const std::string& where) {
  FixedConfig c;
  c.half = settings.half;
  c.knobs = settings.preset.empty() ? context.baseKnobs : knobPreset(settings.preset);
  try {
    c.knobs = parseKnobs(settings.knobs, c.knobs);
  } catch (const Error& e) {
    throw Error(where + ": 'knobs': " + e.what());
  }
  return std::make_unique<FixedController>(name, c);
}

}  // namespace sb
