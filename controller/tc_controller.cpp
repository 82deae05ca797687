#include "controller/tc_controller.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "core/config_reader.h"
#include "core/error.h"

namespace sb {

void TcConfig::read(ConfigReader& r) {
  r.string("table", tablePath);
  r.integer("window_frames", windowFrames, 1, 100000);
  r.number("reference_velocity_m_per_frame", referenceVelocity, 1e-6, 1.0);
  r.number("error_budget_m", errorBudgetM, 0.0, 10.0);
  if (const nlohmann::json* t = r.raw("inline_table")) inlineTable = *t;
  r.finish();
  if (inlineTable) {
    table = tcTableFromJson(*inlineTable, r.at("inline_table"));
  } else {
    if (tablePath.empty())
      throw Error(r.where() + ": 'table' is required: the JSON configuration table built by `slambooster profile`");
    table = loadTcTable(tablePath);
  }
}

nlohmann::json TcConfig::toJson() const {
  nlohmann::json j = {{"table", tablePath},
                      {"window_frames", windowFrames},
                      {"reference_velocity_m_per_frame", referenceVelocity},
                      {"error_budget_m", errorBudgetM}};
  if (inlineTable) j["inline_table"] = *inlineTable;
  return j;
}

TcController::TcController(std::string name, TcConfig config) : name_(std::move(name)), config_(std::move(config)) {}

size_t TcController::select(double velocity) const {
  const double scale = std::max(velocity, 0.0) / config_.referenceVelocity;
  size_t best = 0;
  for (size_t i = 0; i < config_.table.entries.size(); ++i)
    if (config_.table.entries[i].ateM * scale <= config_.errorBudgetM) best = i;  // by increasing speedup
  return best;
}

Decision TcController::decide(const Observation& o) {
  Decision d;
  velocitySum_ += o.velocity;
  if (++inWindow_ >= config_.windowFrames) {
    const size_t chosen = select(velocitySum_ / inWindow_);
    if (chosen < entry_) d.triggers |= kTriggerBudget;  // the error budget forced a slower entry
    entry_ = chosen;
    velocitySum_ = 0.0;
    inWindow_ = 0;
  }
  d.level = static_cast<int>(entry_);
  d.next = config_.table.entries[entry_].knobs;
  return d;
}

}  // namespace sb
