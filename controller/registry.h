#pragma once
// Creating controllers by name (architecture.md D4). Names and what they are: `controllerNames()` and
// `slambooster run --help`. The config's controller section (config/controller.json) is either a name or
// {"name": NAME, "<section>": {...}, ...} with one parameter object per controller family ("fixed",
// "slambooster", "adaptive", "step", "tc", "offline", "budget"). Parsing validates every section present, so
// an error in a section not selected is still reported at start-up, and a later switch by name (socket,
// SIGHUP) can not fail on bad parameters.
//
// Adding a controller: its file pair (the controller and its settings struct, with read(ConfigReader&) and
// toJson()) plus one controllerType(...) line in registry.cpp, as a power meter (power/meter_registry.h).

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "controller/controller.h"
#include "core/config_reader.h"

namespace sb {

// Creates a controller from its read settings; `where` names the section in messages ("file: controller.tc").
template <typename Settings>
using CreateController = std::unique_ptr<Controller> (*)(const std::string& name, const Settings& settings,
                                                         const ControllerContext& context,
                                                         const std::string& where);

struct ControllerType {
  std::string name;
  std::string section;  // the parameter section it reads ("" = none: it runs on its settings' defaults)
  std::string help;     // one line for --help
  // The section's settings with every key at its default (the struct's toJson(); config/controller.json and
  // config/README.md are tested against it).
  std::function<nlohmann::json()> defaults;
  // Reads the section `params` ({} when absent) with the config reader and creates the controller.
  std::function<std::unique_ptr<Controller>(const nlohmann::json& params, const std::string& where,
                                            const ControllerContext& context)>
      create;
};

// Reads `section` into a settings struct with read(ConfigReader&) and refuses unknown keys.
template <typename Settings>
Settings readControllerSettings(const nlohmann::json& section, const std::string& where) {
  ConfigReader r(section, where);
  Settings s;
  s.read(r);
  r.finish();
  return s;
}

// A registry entry for a controller whose settings struct has read(ConfigReader&) and toJson().
template <typename Settings>
ControllerType controllerType(const char* name, const char* section, const char* help,
                              CreateController<Settings> create) {
  ControllerType t;
  t.name = name;
  t.section = section;
  t.help = help;
  t.defaults = [] { return Settings{}.toJson(); };
  t.create = [name = t.name, create](const nlohmann::json& params, const std::string& where,
                                     const ControllerContext& context) {
    return create(name, readControllerSettings<Settings>(params, where), context, where);
  };
  return t;
}

// A CreateController for a controller constructed from its name and settings.
template <typename Impl, typename Settings>
std::unique_ptr<Controller> construct(const std::string& name, const Settings& settings,
                                      const ControllerContext&, const std::string&) {
  return std::make_unique<Impl>(name, settings);
}

// The registered controllers, in registry order.
const std::vector<ControllerType>& controllerTypes();

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
std::unique_ptr<Controller> createController(const ControllerSettings& settings,
                                             const ControllerContext& context);
// The same with another name (switching between frames keeps the other sections).
std::unique_ptr<Controller> createController(const std::string& name, const ControllerSettings& settings,
                                             const ControllerContext& context);

}  // namespace sb
