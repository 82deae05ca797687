#pragma once
// `fixed`: the same knobs every frame (architecture.md D4). The presets `default` and `accurate` are the
// knob table's (architecture.md D2); `offline` replays the best setting of `slambooster dse` the same way.
//
// Section keys: "preset" ("default" | "accurate"; absent = the pipeline config's knobs), "knobs" (a knob
// string applied on top, e.g. "csr=2,icp=1e-4"), "half" (bool: wish half precision).

#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "controller/controller.h"

namespace sb {

struct FixedConfig {
  Knobs knobs;
  bool half = false;
};

class FixedController final : public Controller {
 public:
  FixedController(std::string name, const FixedConfig& config) : name_(std::move(name)), config_(config) {}
  const std::string& name() const override { return name_; }
  Knobs initialKnobs() const override { return config_.knobs; }
  Decision decide(const Observation& observation) override;

 private:
  std::string name_;
  FixedConfig config_;
};

// Reads a `fixed` section on top of `base` knobs (with `preset` preselected when not empty).
FixedConfig parseFixedConfig(const nlohmann::json& section, const std::string& where, const Knobs& base,
                             const std::string& preset = "");

}  // namespace sb
