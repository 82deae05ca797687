#include "controller/registry.h"


#include "controller/adaptive_controller.h"
#include "controller/budget_controller.h"
#include "controller/fixed_controller.h"
#include "controller/offline_controller.h"
#include "controller/slambooster_controller.h"
#include "controller/step_controller.h"
#include "controller/tc_controller.h"
#include "core/error.h"
#include "core/input_file.h"

namespace sb {

namespace {

// slambooster with some parts switched off (the incremental study): 0 the PID part only, 1 + surface,
// 2 + correction; half precision off in all three.
template <int parts>
std::unique_ptr<Controller> slamBoosterParts(const std::string& name, const SlamBoosterConfig& settings,
                                             const ControllerContext&, const std::string&) {
  SlamBoosterConfig c = settings;
  c.surfaceDetection = parts >= 1;
  c.poseCorrection = parts >= 2;
  c.halfPrecision = false;
  return std::make_unique<SlamBoosterController>(name, c);
}

// A fixed preset: no section of its own.
template <const char* preset>
std::unique_ptr<Controller> fixedPreset(const std::string& name, const FixedSettings& settings,
                                        const ControllerContext& context, const std::string& where) {
  FixedSettings s = settings;
  s.preset = preset;
  return createFixedController(name, s, context, where);
}
constexpr char kDefault[] = "default";
constexpr char kAccurate[] = "accurate";

}  // namespace

// One line per controller.
const std::vector<ControllerType>& controllerTypes() {
  static const std::vector<ControllerType> table = {
      controllerType("fixed", "fixed", "the same knobs every frame (section: preset, knobs, half)",
                     createFixedController),
      controllerType("default", "", "fixed, SLAMBench's default knobs (csr=1,icp=1e-5,pd=10:5:4,ir=2)",
                     fixedPreset<kDefault>),
      controllerType("accurate", "", "fixed, the most accurate knobs (icp=0, ir=1)", fixedPreset<kAccurate>),
      controllerType("slambooster", "slambooster",
                     "the paper's controller: PID on velocity, surface, correction, half",
                     construct<SlamBoosterController, SlamBoosterConfig>),
      controllerType("pid", "slambooster", "slambooster's PID part only", slamBoosterParts<0>),
      controllerType("pid+surface", "slambooster", "PID + smooth-surface detection", slamBoosterParts<1>),
      controllerType("pid+surface+correction", "slambooster",
                     "PID + surface + pose correction (no half precision)", slamBoosterParts<2>),
      controllerType(
          "adaptive", "adaptive",
          "the product's controller: levels, re-tracking and integration from the tracker's evidence",
          construct<AdaptiveController, AdaptiveConfig>),
      controllerType("step", "step", "hierarchical step controller (csr, then icp, then pd0)",
                     construct<StepController, StepConfig>),
      controllerType("budget", "budget", "least approximation meeting a target ms or J per frame",
                     construct<BudgetController, BudgetConfig>),
      controllerType("tc", "tc", "application-agnostic window controller over a `slambooster profile` table",
                     construct<TcController, TcConfig>),
      controllerType("offline", "offline", "replays the best fixed setting of `slambooster dse`",
                     createOfflineController),
  };
  return table;
}

namespace {

const ControllerType& findEntry(const std::string& name, const std::string& where) {
  for (const ControllerType& e : controllerTypes())
    if (name == e.name) return e;
  std::string names;
  for (const ControllerType& e : controllerTypes()) names += (names.empty() ? "" : ", ") + e.name;
  // Quoted with control bytes escaped: a NUL inside the name (a request's "\u0000") must not cut the message.
  throw Error(where + ": unknown controller " + quoteForMessage(name) + " (known: " + names + ")");
}

bool isSection(const std::string& key) {
  for (const ControllerType& e : controllerTypes())
    if (key == e.section) return true;
  return false;
}

}  // namespace

std::vector<std::string> controllerNames() {
  std::vector<std::string> names;
  for (const ControllerType& e : controllerTypes()) names.emplace_back(e.name);
  return names;
}

std::string controllerHelp() {
  std::string text;
  for (const ControllerType& e : controllerTypes()) text += "  " + e.name + ": " + e.help + "\n";
  return text;
}

ControllerSettings parseControllerSettings(const nlohmann::json& j, const ControllerContext& context,
                                           const std::string& where) {
  ControllerSettings s;
  s.where = where;
  if (j.is_string()) {
    s.name = j.get<std::string>();
  } else if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (it.key() == "name") {
        if (!it->is_string())
          throw Error(where + ": 'name' must be a controller name string, got " + it->dump());
        s.name = it->get<std::string>();
      } else if (!it.key().empty() && isSection(it.key())) {
        if (!it->is_object())
          throw Error(where + ": '" + it.key() + "' must be an object of parameters, got " + it->dump());
        s.sections[it.key()] = *it;
      } else {
        std::string keys = "name";
        for (const ControllerType& e : controllerTypes())
          if (!e.section.empty() && keys.find(e.section) == std::string::npos) keys += ", " + e.section;
        throw Error(where + ": unknown key '" + it.key() + "' (known keys: " + keys + ")");
      }
    }
  } else {
    throw Error(where + ": must be a controller name or an object {\"name\": ..., <section>: {...}}, got " +
                j.dump());
  }
  findEntry(s.name, where + ".name");
  // Validate every section present once, and the selected controller.
  for (const ControllerType& e : controllerTypes())
    if (!e.section.empty() && s.sections.contains(e.section)) createController(e.name, s, context);
  createController(s.name, s, context);
  return s;
}

std::unique_ptr<Controller> createController(const std::string& name, const ControllerSettings& settings,
                                             const ControllerContext& context) {
  const ControllerType& e = findEntry(name, settings.where);
  const nlohmann::json params = !e.section.empty() && settings.sections.contains(e.section)
                                    ? settings.sections.at(e.section)
                                    : nlohmann::json::object();
  return e.create(params, settings.where + "." + (e.section.empty() ? e.name : e.section), context);
}

std::unique_ptr<Controller> createController(const ControllerSettings& settings,
                                             const ControllerContext& context) {
  return createController(settings.name, settings, context);
}

}  // namespace sb
