#pragma once
// `offline`: replays the best fixed setting that `slambooster dse SEQ` found for a whole trajectory (the
// fastest knobs whose ATE stayed under the bound), as a fixed controller.

#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "controller/controller.h"
#include "core/config_reader.h"

namespace sb {

// The `offline` section: exactly one of its keys.
struct OfflineSettings {
  std::string result;  // the dse output's best.json
  std::string knobs;   // a knob string, e.g. copied from it

  // Section keys: result, knobs. Calls reader.finish(), then refuses settings with neither or both.
  void read(ConfigReader& reader);
  nlohmann::json toJson() const;  // every key read() reads, with its value
};

// Reads {"knobs": "csr=..."} at the top level or under "best" of a dse result file.
Knobs loadDseBestKnobs(const std::string& path);

std::unique_ptr<Controller> createOfflineController(const std::string& name, const OfflineSettings& settings,
                                                    const ControllerContext& context,
                                                    const std::string& where);

}  // namespace sb
