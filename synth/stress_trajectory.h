#pragma once
// Stress trajectories for the controller experiments (issue 5), deterministic for (scene, seed), 30 fps,
// handheld-like (small hand sway everywhere), camera-to-world in the scenes' world frame (floor at +y):
//
// - bursts: calm stretches (slow drift and look-around, under ~0.15 m/s and ~20 deg/s) broken by four short
//   bursts (0.5 s each) of fast motion: a sideways jerk peaking at ~1 m/s, a yaw flick peaking at ~110
//   deg/s, a swing (both at once, ~0.9 m/s and ~90 deg/s) and a pitch flick, in a seeded order. The camera
//   stays near the built-in orbit's centre, in the rooms' free floor space, looking at the furnished
//   south-east corner.
// - blank-wall: the camera looks at furnished parts of the room (of the directions 60-120 degrees off the
//   wall, the one with the most depth structure), turns to the blank stretch (Scene::blankWalls) with the
//   most free floor in front of it, walks up to 0.75 m from it, pans slowly along it for 6 s (the view is
//   one plane: the smooth-surface detector fires and ICP is ill-conditioned in the wall's plane), walks back
//   and turns to the furnished parts again.
//
// Every motion is a minimum-jerk move between key states, so speeds are smooth and the peaks are known:
// a move of distance d over T seconds peaks at 1.875 d / T.

#include <cstdint>
#include <string>
#include <vector>

#include "core/trajectory.h"
#include "synth/scene.h"

namespace sb::synth {

enum class StressKind { Bursts, BlankWall };

// "bursts", "blank-wall" (the names `slambooster synth --stress` takes).
const std::vector<std::string>& stressNames();
// Throws sb::Error for an unknown name (listing the known ones).
StressKind parseStressKind(const std::string& name);

struct StressParams {
  double fps = 30.0;             // frames per second
  double swayPositionM = 0.012;  // amplitude of the hand sway in position, metres
  double swayAngleRad = 0.015;   // amplitude of the hand sway in yaw/pitch/roll, radians
  // bursts
  double burstDurationS = 0.5;            // seconds per burst
  double burstSpeedMps = 1.0;             // peak translation speed of a sideways burst, metres per second
  double burstRateDegps = 110.0;          // peak rotation rate of a yaw burst, degrees per second
  double calmMinS = 2.4, calmMaxS = 3.2;  // seconds of calm before each burst (seeded)
  // blank-wall
  double wallDistanceM = 0.75;  // camera-to-wall distance while facing the blank stretch, metres
  double blankSeconds = 6.0;    // seconds facing the blank stretch
  double panAlongM = 0.1;       // slide along the wall each way during the pan, metres
};

struct StressSegment {
  std::string label;  // bursts: calm, burst; blank-wall: furnished, turn, approach, blank-wall, retreat
  size_t begin = 0, end = 0;  // frames [begin, end)
};

struct StressTrajectory {
  Trajectory poses;                     // timestamps i / fps
  std::vector<StressSegment> segments;  // in order, covering every frame
};

// `scene` must be a generated room (blank-wall needs its blankWalls). Throws sb::Error otherwise.
StressTrajectory stressTrajectory(StressKind kind, const Scene& scene, uint64_t seed,
                                  const StressParams& params = {});

}  // namespace sb::synth
