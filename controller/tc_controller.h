#pragma once
// `tc`: the application-agnostic baseline (POET / JouleGuard style; architecture.md D4). It knows nothing of
// SLAM beyond one error signal: per window of `window_frames` frames it measures the mean camera velocity
// v_w and assumes the error of a table entry scales with v_w / v_ref (the profiling sequences' reference
// velocity). For the next window it runs the fastest entry whose scaled profiled ATE fits the error budget:
//   ate_m * v_w / v_ref <= error_budget_m.
// No surface detection, no pose correction. The first window runs the table's most accurate entry.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "controller/controller.h"
#include "controller/tc_table.h"
#include "core/config_reader.h"

namespace sb {

struct TcConfig {
  std::string tablePath;              // JSON from `slambooster profile` (required)
  int windowFrames = 32;              // 32 or 64 in the paper
  double referenceVelocity = 0.01;    // m/frame: v_ref
  double errorBudgetM = 0.05;         // metres of ATE
  std::optional<nlohmann::json> inlineTable;  // the table itself instead of a file
  TcTable table;                      // loaded from tablePath or inlineTable

  // Section keys: table, window_frames, reference_velocity_m_per_frame, error_budget_m, inline_table. Calls
  // reader.finish(), then loads the table (required).
  void read(ConfigReader& reader);
  nlohmann::json toJson() const;  // every key read() reads (inline_table when set), with its value
};

class TcController final : public Controller {
 public:
  TcController(std::string name, TcConfig config);
  const std::string& name() const override { return name_; }
  Knobs initialKnobs() const override { return config_.table.entries.front().knobs; }
  Decision decide(const Observation& observation) override;
  // The entry index the window velocity `v` selects.
  size_t select(double velocity) const;

 private:
  std::string name_;
  TcConfig config_;
  size_t entry_ = 0;
  double velocitySum_ = 0.0;
  int inWindow_ = 0;
};

}  // namespace sb
