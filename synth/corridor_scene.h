#pragma once
// A long corridor for the robot drives (stress `drive`): a straight corridor along world +z from z = 0 to
// its length, its floor at y = kCorridorFloorY (world +y is down, as in the rooms), with seeded irregular
// structure on both walls: door recesses (the door set back into the wall), side openings into shallow
// alcoves (sometimes with a box in them), pillars, floor cabinets, vertical riser pipes; pipe runs along the
// walls under the ceiling and ceiling lights. Most of it is flat or runs along the corridor, so, as in a real
// corridor, what fixes the motion along the axis is the occasional edge across it.
//
// The walls are boxes (the scene's RoomBox lies kWallDepthM behind them, where openings and recesses end),
// so Scene::insideRoom alone does not say a point is in the corridor: objectContaining does.

#include <cstdint>

#include "synth/scene.h"

namespace sb::synth {

inline const char* const kCorridorSceneName = "corridor";
constexpr float kCorridorFloorY = 1.2f;  // world y of the floor, metres (a camera 1.2 m up is at y = 0)

struct CorridorParams {
  double lengthM = 20.0;    // along +z, metres
  double widthM = 2.2;      // wall to wall, metres
  double heightM = 2.6;     // floor to ceiling, metres
  double wallDepthM = 1.4;  // from the wall surface to the RoomBox behind it (openings' depth), metres
  // Clear of everything but the walls: the drive's lanes need this much either side of the axis, metres.
  double clearHalfWidthM = 0.7;
  // Spacing of the structure: the gaps between wall features and between ceiling lights are scaled by this
  // (1 = gaps of 0.3-1.5 m and lights every 2.4-3.6 m). At 4 and more, stretches of the drive see nothing
  // across the corridor that fixes motion along it.
  double spacingScale = 1.0;
};

// Throws sb::Error for dimensions out of range (length 4-200 m, width 1.6-4 m, height 2.2-4 m, spacing scale
// 0.5-20).
Scene generateCorridor(uint64_t seed, const CorridorParams& params = {});

}  // namespace sb::synth
