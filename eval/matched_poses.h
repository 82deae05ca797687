#pragma once
// The associated poses of two trajectories, in time order, shared by ATE and RPE. Raises the user-facing
// errors for empty trajectories, no overlap in time and too few matches.

#include <cstddef>

#include "eval/trajectory_eval.h"

namespace sb {

struct MatchedPoses {
  Trajectory estimate;     // estimate poses of the matches, increasing time (original timestamps)
  Trajectory groundTruth;  // the ground-truth pose matched to each of them
};

// Throws sb::Error naming the time ranges of both trajectories when fewer than `minMatches` associate.
MatchedPoses matchPoses(const Trajectory& estimate, const Trajectory& groundTruth,
                        const AssociationOptions& options, size_t minMatches);

}  // namespace sb
