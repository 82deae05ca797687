#pragma once
// The drive stress (stress_trajectory.h describes it): a wheeled robot driving a corridor's length and back,
// in the corridor scene (corridor_scene.h).

#include "synth/rng.h"
#include "synth/scene.h"
#include "synth/stress_trajectory.h"

namespace sb::synth::stress {

// `scene` must be generateCorridor's. Throws sb::Error otherwise, or when the corridor is too short to reach
// the cruise speed.
StressTrajectory driveTrajectory(const Scene& scene, const StressParams& p, Rng& rng);

}  // namespace sb::synth::stress
