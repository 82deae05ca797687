#pragma once
// `fixed`: the same knobs every frame (architecture.md D4). The presets `default` and `accurate` are the
// knob table's (architecture.md D2); `offline` replays the best setting of `slambooster dse` the same way.

#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "controller/controller.h"
#include "core/config_reader.h"

namespace sb {

// The `fixed` section.
struct FixedSettings {
  std::string preset;  // "default" | "accurate"; empty = the pipeline config's knobs
  std::string knobs;   // a knob string applied on top, e.g. "csr=2,icp=1e-4"
  bool half = false;   // wish half precision

  // Section keys: preset, knobs, half.
  void read(ConfigReader& reader);
  nlohmann::json toJson() const;  // every key read() reads, with its value
};

// What a fixed controller runs.
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

// `settings` on top of the context's knobs. Throws sb::Error naming `where` and 'knobs' for a bad knob
// string.
std::unique_ptr<Controller> createFixedController(const std::string& name, const FixedSettings& settings,
                                                  const ControllerContext& context, const std::string& where);

}  // namespace sb
