#pragma once
// `offline`: replays the best fixed setting that `slambooster dse SEQ` found for a whole trajectory (the
// fastest knobs whose ATE stayed under the bound), as a fixed controller.
// Section keys: "result" (the dse output's best.json) or "knobs" (a knob string, e.g. copied from it).

#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "controller/controller.h"

namespace sb {

// Reads {"knobs": "csr=..."} at the top level or under "best" of a dse result file.
Knobs loadDseBestKnobs(const std::string& path);

std::unique_ptr<Controller> createOfflineController(const nlohmann::json& section, const std::string& where);

}  // namespace sb
