#pragma once
// JSON forms of per-frame energy and run totals: energy.jsonl's lines, `slambooster energy --json` and the
// daemon's STATUS. Unknown values (NaN) become null. (summary.json's "energy" is typed: report/run_summary.h
// EnergySummary, filled by runtime/energy_account.h.)
//
//   out << sb::power::frameEnergyJson(e).dump() << "\n";      // one line of energy.jsonl

#include <cstddef>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "power/energy_ledger.h"
#include "power/sample.h"

namespace sb::power {

// frame, t_start_mono_ns, t_end_mono_ns, known, joules, joules_above_idle, mean_watts (+ unknown_reason).
nlohmann::json frameEnergyJson(const FrameEnergy& e);

// frames, known_frames, unknown_frames, joules, joules_per_frame, mean_watts, seconds, idle_watts,
// joules_above_idle, span_seconds, span_known_seconds, span_joules, span_mean_watts, unknown_reasons.
nlohmann::json energyTotalsJson(const EnergyTotals& t, const std::map<std::string, size_t>& unknownReasons);

}  // namespace sb::power
