#pragma once
// The stress kinds whose stress is the motion itself (stress_trajectory.h describes them all): pan and
// robot. (hard-bursts is bursts with harder parameters, in stress_trajectory.cpp; corridor is in
// stress_corridor.h.)

#include "synth/rng.h"
#include "synth/scene.h"
#include "synth/stress_trajectory.h"

namespace sb::synth::stress {

StressTrajectory panTrajectory(const Scene& scene, const StressParams& p, Rng& rng);
// Throws sb::Error when no loop of the robot's fits the scene's free floor space.
StressTrajectory robotTrajectory(const Scene& scene, const StressParams& p, Rng& rng);

}  // namespace sb::synth::stress
