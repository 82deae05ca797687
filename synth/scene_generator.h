#pragma once
// Procedural rooms: generateScene(name, seed) builds a furnished room whose free floor space encloses the
// camera positions of the four handheld ICL-NUIM living-room trajectories (livingroom0..3, world frame as in
// their TUM files, floor at +y) and the built-in trajectory. Furniture stands along the walls outside that
// free space (low pieces such as a coffee table may stand inside it), every wall keeps a stretch of blank
// wall (Scene::blankWalls), and a column stands in the gap that the livingroom3 loop walks around. Above the
// furniture, each wall carries one or two thin panels (pictures / whiteboards) and then a run of wall
// fixtures (framed pictures, shelves with books, vases and boxes, hung cabinets) at heights below and above
// the cameras' eye level, outside the blank stretch: without them a camera close to a wall saw one or two
// plane orientations (a bare wall, a wall and the front of a sofa) and ICP could slide along the wall (the
// livingroom/office ICL-NUIM sequences 1-3 drifted by 8-42 cm). Different seeds vary the choice, size and
// placement of furniture and fixtures; the room and the free space are the same for every seed.

#include <cstdint>
#include <string>
#include <vector>

#include "synth/scene.h"

namespace sb::synth {

// The scene names generateScene accepts.
const std::vector<std::string>& sceneNames();

// Throws sb::Error for an unknown name (listing the known ones).
Scene generateScene(const std::string& name, uint64_t seed);

}  // namespace sb::synth
