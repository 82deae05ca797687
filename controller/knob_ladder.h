#pragma once
// The discrete knob levels a controller moves between (architecture.md D2, level 0 = most accurate) and the
// original SLAMBooster coupling of one approximation level L to the knobs: csr level L, icp level
// offset + L / divisor (1e-5 at L 0-1, 1e-4 at L 2-3), pd0 level L, fixed pd1/pd2, tr and ir.

#include <vector>

#include "core/config_reader.h"
#include "pipeline/knobs.h"

namespace sb {

struct KnobLadder {
  std::vector<int> csrLevels{1, 2, 4, 8};                     // compute size ratio per level
  std::vector<double> icpLevels{0.0, 1e-6, 1e-5, 1e-4, 1e-3, 1.0};  // ICP early-stop threshold per level
  std::vector<int> pd0Levels{10, 8, 6, 4};                    // finest-level ICP iterations per level
  int pd1 = 5;                                                // mid-level ICP iterations (fixed)
  int pd2 = 4;                                                // coarsest-level ICP iterations (fixed)
  int icpLevelOffset = 2;                                     // icp level = offset + L / divisor
  int icpLevelDivisor = 2;
  int maxLevel = 3;                                           // highest coupled approximation level
  int trackingRate = 1;                                       // tr of every level
  int integrationRate = 1;                                    // ir of every level

  // Knobs of coupled level L (clamped to [0, maxLevel]; each knob's level clamped to its list).
  Knobs coupled(int level) const;
  // Knobs of independent levels per knob (clamped to each list).
  Knobs at(int csrLevel, int icpLevel, int pd0Level) const;

  // Reads the keys csr_levels, icp_levels, pd0_levels, pd1, pd2, icp_level_offset, icp_level_divisor,
  // max_level, tr, ir; validates the result (each level a valid knob value).
  void read(ConfigReader& reader);
  void toJson(nlohmann::json& section) const;  // adds the same keys with their values
};

}  // namespace sb
