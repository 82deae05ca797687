#pragma once
// Creating controllers by name (architecture.md D4). Names and what they are: `controllerNames()` and
// `slambooster run --help`. The config's controller section (config/controller.json) is either a name or
// {"name": NAME, "<section>": {...}, ...} with one parameter object per controller family ("fixed",
// "slambooster", "adaptive", "step", "tc", "offline", "budget"). Parsing validates every section present, so an error
// in a section not selected is still reported at start-up, and a later switch by name (socket, SIGHUP) can
// not fail on bad parameters.

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "controller/controller.h"

namespace sb {

// What a controller may borrow from the run it controls.
struct ControllerContext {
  Knobs baseKnobs;  // the pipeline config's knobs (what `fixed` without a preset runs)
};

struct ControllerSettings {
  std::string name = "fixed";
  nlohmann::json sections = nlohmann::json::object();  // section name -> parameter object
  std::string where = "controller";                    // prefix of error messages (file and key)
};

// The registered names, in registry order.
std::vector<std::string> controllerNames();
// "name: one-line description" per controller, for --help.
std::string controllerHelp();

// Reads the controller section `j` (a name string or an object; see above) and validates it. Throws
// sb::Error naming `where`, the key, the value and the fix.
ControllerSettings parseControllerSettings(const nlohmann::json& j, const ControllerContext& context,
                                           const std::string& where = "controller");

// Creates the controller `settings.name` with its section's parameters. Throws sb::Error for an unknown name.
std::unique_ptr<Controller> createController(const ControllerSettings& settings, const ControllerContext& context);
// The same with another name (switching between frames keeps the other sections).
std::unique_ptr<Controller> createController(const std::string& name, const ControllerSettings& settings,
                                             const ControllerContext& context);

}  // namespace sb
