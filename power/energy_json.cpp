#include "power/energy_json.h"

#include <cmath>

namespace sb::power {
namespace {

nlohmann::json number(double v) { return std::isnan(v) ? nlohmann::json(nullptr) : nlohmann::json(v); }

}  // namespace

nlohmann::json frameEnergyJson(const FrameEnergy& e) {
  nlohmann::json j = {{"frame", e.frame},
                      {"t_start_mono_ns", e.startNs},
                      {"t_end_mono_ns", e.endNs},
                      {"known", e.known},
                      {"joules", number(e.joules)},
                      {"joules_above_idle", number(e.joulesAboveIdle)},
                      {"mean_watts", number(e.meanWatts)}};
  if (!e.known) j["unknown_reason"] = e.unknownReason;
  return j;
}

nlohmann::json energyTotalsJson(const EnergyTotals& t, const std::map<std::string, size_t>& unknownReasons) {
  return {{"frames", t.frames},
          {"known_frames", t.knownFrames},
          {"unknown_frames", t.unknownFrames},
          {"joules", t.joules},
          {"joules_per_frame", number(t.joulesPerFrame())},
          {"mean_watts", number(t.meanWatts())},
          {"seconds", t.seconds},
          {"idle_watts", t.idleWatts},
          {"joules_above_idle", t.joulesAboveIdle},
          {"span_seconds", t.spanSeconds},
          {"span_known_seconds", t.spanKnownSeconds},
          {"span_joules", t.spanJoules},
          {"span_mean_watts", number(t.spanMeanWatts())},
          {"unknown_reasons", unknownReasons}};
}

}  // namespace sb::power
