#pragma once
// The kidnap stresses (stress_trajectory.h describes them): calm handheld mapping of part of the room, the
// lens covered (no depth) for a seeded 1-3 s while the camera moves elsewhere, then shown a place seen
// before (kidnap) or a place no mapping frame saw (kidnap-unseen).

#include "synth/rng.h"
#include "synth/scene.h"
#include "synth/stress_trajectory.h"

namespace sb::synth::stress {

// kidnap: the view after the cover is lifted is close to a mapping key view (seeded, at least the kidnap's
// minimum jump away from where the cover went on); it then moves calmly over mapped views.
StressTrajectory kidnapTrajectory(const Scene& scene, const StressParams& p, Rng& rng);

// kidnap-unseen: the view after the cover is lifted (and its look-around) sees almost nothing a mapping
// frame saw (SeenSurfaces::seenFraction at most p.kidnapMaxSeenFraction) while holding structure that would
// track. Throws sb::Error when no such view is reachable while covered.
StressTrajectory kidnapUnseenTrajectory(const Scene& scene, const StressParams& p, Rng& rng);

}  // namespace sb::synth::stress
