#include "controller/knob_ladder.h"

#include <algorithm>

#include "core/error.h"

namespace sb {

namespace {

template <typename T>
T pick(const std::vector<T>& levels, int level) {
  return levels[static_cast<size_t>(std::clamp(level, 0, static_cast<int>(levels.size()) - 1))];
}

}  // namespace

Knobs KnobLadder::at(int csrLevel, int icpLevel, int pd0Level) const {
  Knobs k;
  k.csr = pick(csrLevels, csrLevel);
  k.icpThreshold = pick(icpLevels, icpLevel);
  k.pyramidIterations = {pick(pd0Levels, pd0Level), pd1, pd2};
  k.trackingRate = trackingRate;
  k.integrationRate = integrationRate;
  return k;
}

Knobs KnobLadder::coupled(int level) const {
  const int l = std::clamp(level, 0, maxLevel);
  return at(l, icpLevelOffset + l / icpLevelDivisor, l);
}

void KnobLadder::read(ConfigReader& r) {
  r.integers("csr_levels", csrLevels, 1, 8, 1, 8);
  r.numbers("icp_levels", icpLevels, 0.0, 1.0, 1, 16);
  r.integers("pd0_levels", pd0Levels, 1, kMaxIterations, 1, 16);
  r.integer("pd1", pd1, 0, kMaxIterations);
  r.integer("pd2", pd2, 0, kMaxIterations);
  r.integer("icp_level_offset", icpLevelOffset, 0, 15);
  r.integer("icp_level_divisor", icpLevelDivisor, 1, 16);
  r.integer("max_level", maxLevel, 0, 15);
  r.integer("tr", trackingRate, 1, kMaxRate);
  r.integer("ir", integrationRate, 1, kMaxRate);
  for (int l = 0; l <= maxLevel; ++l) {
    try {
      validateKnobs(coupled(l));
    } catch (const Error& e) {
      throw Error(r.where() + ": level " + std::to_string(l) + " gives invalid knobs: " + e.what());
    }
  }
  for (int csr : csrLevels)
    if (csr != 1 && csr != 2 && csr != 4 && csr != 8)
      throw Error(r.at("csr_levels") + ": " + std::to_string(csr) + " is not a compute size ratio (use 1, 2, 4, 8)");
}

void KnobLadder::toJson(nlohmann::json& j) const {
  j["csr_levels"] = csrLevels;
  j["icp_levels"] = icpLevels;
  j["pd0_levels"] = pd0Levels;
  j["pd1"] = pd1;
  j["pd2"] = pd2;
  j["icp_level_offset"] = icpLevelOffset;
  j["icp_level_divisor"] = icpLevelDivisor;
  j["max_level"] = maxLevel;
  j["tr"] = trackingRate;
  j["ir"] = integrationRate;
}

}  // namespace sb
