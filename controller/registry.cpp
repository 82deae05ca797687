#include "controller/registry.h"

#include <functional>

#include "controller/adaptive_controller.h"
#include "controller/budget_controller.h"
#include "controller/fixed_controller.h"
#include "controller/offline_controller.h"
#include "controller/slambooster_controller.h"
#include "controller/step_controller.h"
#include "controller/tc_controller.h"
#include "core/error.h"

namespace sb {

namespace {

using Factory = std::function<std::unique_ptr<Controller>(const nlohmann::json& params, const std::string& where,
                                                          const ControllerContext& context)>;

struct Entry {
  const char* name;
  const char* section;  // the parameter section it reads ("" = none)
  const char* help;
  Factory create;
};

Factory fixedPreset(const char* name, const char* preset) {
  return [name, preset](const nlohmann::json& params, const std::string& where, const ControllerContext& context) {
    return std::make_unique<FixedController>(name, parseFixedConfig(params, where, context.baseKnobs, preset));
  };
}

// slambooster with some parts switched off (the incremental study); "all" keeps the section's switches.
Factory slamBoosterVariant(const char* name, int parts) {
  return [name, parts](const nlohmann::json& params, const std::string& where, const ControllerContext&) {
    SlamBoosterConfig c = parseSlamBoosterConfig(params, where);
    if (parts >= 0) {
      c.surfaceDetection = parts >= 1;
      c.poseCorrection = parts >= 2;
      c.halfPrecision = false;
    }
    return std::make_unique<SlamBoosterController>(name, c);
  };
}

template <typename Config, typename Impl, Config (*parse)(const nlohmann::json&, const std::string&)>
Factory simple(const char* name) {
  return [name](const nlohmann::json& params, const std::string& where, const ControllerContext&) {
    return std::make_unique<Impl>(name, parse(params, where));
  };
}

// One line per controller.
const std::vector<Entry>& entries() {
  static const std::vector<Entry> table = {
      {"fixed", "fixed", "the same knobs every frame (section: preset, knobs, half)", fixedPreset("fixed", "")},
      {"default", "", "fixed, SLAMBench's default knobs (csr=1,icp=1e-5,pd=10:5:4,ir=2)", fixedPreset("default", "default")},
      {"accurate", "", "fixed, the most accurate knobs (icp=0, ir=1)", fixedPreset("accurate", "accurate")},
      {"slambooster", "slambooster", "the paper's controller: PID on velocity, surface, correction, half",
       slamBoosterVariant("slambooster", -1)},
      {"pid", "slambooster", "slambooster's PID part only", slamBoosterVariant("pid", 0)},
      {"pid+surface", "slambooster", "PID + smooth-surface detection", slamBoosterVariant("pid+surface", 1)},
      {"pid+surface+correction", "slambooster", "PID + surface + pose correction (no half precision)",
       slamBoosterVariant("pid+surface+correction", 2)},
      {"adaptive", "adaptive", "the product's controller: levels, re-tracking and integration from the tracker's evidence",
       simple<AdaptiveConfig, AdaptiveController, parseAdaptiveConfig>("adaptive")},
      {"step", "step", "hierarchical step controller (csr, then icp, then pd0)",
       simple<StepConfig, StepController, parseStepConfig>("step")},
      {"budget", "budget", "least approximation meeting a target ms or J per frame",
       simple<BudgetConfig, BudgetController, parseBudgetConfig>("budget")},
      {"tc", "tc", "application-agnostic window controller over a `slambooster profile` table",
       simple<TcConfig, TcController, parseTcConfig>("tc")},
      {"offline", "offline", "replays the best fixed setting of `slambooster dse`",
       [](const nlohmann::json& params, const std::string& where, const ControllerContext&) {
         return createOfflineController(params, where);
       }},
  };
  return table;
}

const Entry& findEntry(const std::string& name, const std::string& where) {
  for (const Entry& e : entries())
    if (name == e.name) return e;
  std::string names;
  for (const Entry& e : entries()) names += (names.empty() ? "" : ", ") + std::string(e.name);
  throw Error(where + ": unknown controller '" + name + "' (known: " + names + ")");
}

bool isSection(const std::string& key) {
  for (const Entry& e : entries())
    if (key == e.section) return true;
  return false;
}

}  // namespace

std::vector<std::string> controllerNames() {
  std::vector<std::string> names;
  for (const Entry& e : entries()) names.emplace_back(e.name);
  return names;
}

std::string controllerHelp() {
  std::string text;
  for (const Entry& e : entries()) text += std::string("  ") + e.name + ": " + e.help + "\n";
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
        if (!it->is_string()) throw Error(where + ": 'name' must be a controller name string, got " + it->dump());
        s.name = it->get<std::string>();
      } else if (!it.key().empty() && isSection(it.key())) {
        if (!it->is_object())
          throw Error(where + ": '" + it.key() + "' must be an object of parameters, got " + it->dump());
        s.sections[it.key()] = *it;
      } else {
        std::string keys = "name";
        for (const Entry& e : entries())
          if (*e.section && keys.find(e.section) == std::string::npos) keys += std::string(", ") + e.section;
        throw Error(where + ": unknown key '" + it.key() + "' (known keys: " + keys + ")");
      }
    }
  } else {
    throw Error(where + ": must be a controller name or an object {\"name\": ..., <section>: {...}}, got " + j.dump());
  }
  findEntry(s.name, where + ".name");
  // Validate every section present once, and the selected controller.
  for (const Entry& e : entries())
    if (*e.section && s.sections.contains(e.section)) createController(e.name, s, context);
  createController(s.name, s, context);
  return s;
}

std::unique_ptr<Controller> createController(const std::string& name, const ControllerSettings& settings,
                                             const ControllerContext& context) {
  const Entry& e = findEntry(name, settings.where);
  const nlohmann::json params =
      *e.section && settings.sections.contains(e.section) ? settings.sections.at(e.section) : nlohmann::json::object();
  return e.create(params, settings.where + "." + (*e.section ? e.section : e.name), context);
}

std::unique_ptr<Controller> createController(const ControllerSettings& settings, const ControllerContext& context) {
  return createController(settings.name, settings, context);
}

}  // namespace sb
