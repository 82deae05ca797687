#pragma once
// The corridor stress (stress_trajectory.h describes it): the camera slides sideways along a blank wall,
// facing it, so that for stretches of frames the wall is the only surface in view.
//
// No generated room has a blank wall long enough (their blank stretches are 1.3 m; the camera sees 1.7 m
// of wall from 1.3 m away), so corridor renders in a copy of the room with one stretch of a long wall
// cleared: every piece of furniture and wall fixture in front of it removed (corridorScene). The rooms
// themselves, and every other sequence, are unchanged.

#include "synth/rng.h"
#include "synth/scene.h"
#include "synth/stress_trajectory.h"

namespace sb::synth::stress {

// `scene` (a generated room) with the corridor's wall stretch cleared. Throws sb::Error when no stretch
// of the room's long walls has furniture beyond both ends.
Scene corridorScene(const Scene& scene, const StressParams& p);

// `scene` is the generated room (not corridorScene's copy): the trajectory is planned, and its frames
// labelled, in corridorScene(scene, p).
StressTrajectory corridorTrajectory(const Scene& scene, const StressParams& p, Rng& rng);

}  // namespace sb::synth::stress
