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
  // The fixed knobs under their names in pipeline/knobs.h's table, with the table's ranges.
  const auto fixed = [&r](const KnobKey& key, int& value) {
    r.integer(key.name, value, static_cast<int>(key.minimum), static_cast<int>(key.maximum));
  };
  fixed(iterationsKey(1), pd1);
  fixed(iterationsKey(2), pd2);
  r.integer("icp_level_offset", icpLevelOffset, 0, 15);
  r.integer("icp_level_divisor", icpLevelDivisor, 1, 16);
  r.integer("max_level", maxLevel, 0, 15);
  fixed(knobKey(&Knobs::trackingRate), trackingRate);
  fixed(knobKey(&Knobs::integrationRate), integrationRate);
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
  j[iterationsKey(1).name] = pd1;
  j[iterationsKey(2).name] = pd2;
  j["icp_level_offset"] = icpLevelOffset;
  j["icp_level_divisor"] = icpLevelDivisor;
  j["max_level"] = maxLevel;
  j[knobKey(&Knobs::trackingRate).name] = trackingRate;
  j[knobKey(&Knobs::integrationRate).name] = integrationRate;
}

}  // namespace sb
