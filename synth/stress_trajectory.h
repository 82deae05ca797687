#pragma once
// Stress trajectories for the controller experiments (issue 5), deterministic for (scene, seed), 30 fps,
// handheld-like (small hand sway everywhere), camera-to-world in the scenes' world frame (floor at +y).
// Both stress the controller's mechanisms while full-precision KinectFusion (DEFAULT) still tracks them, so
// an accuracy bar on them is fair:
//
// - bursts: calm stretches (slow drift and look-around, under ~0.15 m/s and ~15 deg/s) broken by four short
//   bursts (0.5 s each) that move and turn at once, in a seeded order: a sideways jerk peaking at ~1.15 m/s
//   (past the pose corrector's 0.035 m/frame) turning ~30 deg/s to keep the view, a swing (~0.85 m/s, ~50
//   deg/s the same way: the view sweeps fast), a yaw flick with a step (~0.5 m/s, ~55 deg/s) and a nod with
//   a lunge (~0.6 m/s, ~47 deg/s). Rotation stays under 2 deg/frame: at 3 deg/frame DEFAULT's ICP jumped.
//   The camera stays near the built-in orbit's centre, in the rooms' free floor space, looking at the
//   furnished south-east corner.
// - blank-wall: the camera looks at furnished parts of the room, turns (under 1.5 deg/frame) to a blank
//   stretch that ends at a room corner, walks up to it and pans slowly in front of it for 6 s. The view is
//   chosen (stress_views.h) so that the smooth-surface detector's four windows see only the blank wall
//   (it fires on every frame) while the image border outside them holds the corner's side wall and the
//   floor: three plane orientations, so point-to-plane ICP sees every motion. (Facing the middle of a blank
//   wall, ICP slides along it at any precision: DEFAULT drifted 46 cm.) Then it walks back and turns to the
//   furnished parts again.
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
  double burstDurationS = 0.5;   // seconds per burst
  double burstSpeedMps = 1.15;   // peak translation speed of the fastest burst, metres per second
  double burstRateDegps = 55.0;  // peak rotation rate of the fastest-turning burst, degrees per second
  double calmMinS = 2.4, calmMaxS = 3.2;  // seconds of calm before each burst (seeded)
  // blank-wall
  double blankSeconds = 6.0;  // seconds facing the blank stretch
  double panAlongM = 0.06;    // slide along the wall each way during the pan, metres
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
