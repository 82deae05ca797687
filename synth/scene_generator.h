#pragma once
// Procedural rooms: generateScene(name, seed) builds a furnished room whose free floor space encloses the
// camera positions of the four handheld ICL-NUIM living-room trajectories (livingroom0..3, world frame as in
// their TUM files, floor at +y) and the built-in trajectory. Furniture stands along the walls outside that
// free space (low pieces such as a coffee table may stand inside it), every wall keeps a stretch of blank
// wall (Scene::blankWalls), and a column stands in the gap that the livingroom3 loop walks around. Different seeds vary the
// choice, size and placement of furniture; the room and the free space are the same for every seed.

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
