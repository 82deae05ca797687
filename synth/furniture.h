#pragma once
// Furniture built from primitives, in an item frame: x along the wall (centred on 0), z from the wall (0)
// into the room (depth), y down with the floor at y = 0 (so heights are negative y). Metres.

#include <string>
#include <vector>

#include "synth/rng.h"
#include "synth/scene.h"

namespace sb::synth {

struct Item {
  std::string kind;
  std::vector<Primitive> parts;
  float width = 0.f;   // along x, metres
  float depth = 0.f;   // along z, metres
  float height = 0.f;  // metres above the floor
};

using ItemBuilder = Item (*)(Rng& rng);

// Living room.
Item makeSofa(Rng& rng);
Item makeArmchair(Rng& rng);
Item makeBookshelf(Rng& rng);
Item makeTvStand(Rng& rng);
Item makeSideboard(Rng& rng);
Item makeSideTable(Rng& rng);
Item makeFloorLamp(Rng& rng);
Item makePlant(Rng& rng);
Item makeBoxStack(Rng& rng);
Item makeCoffeeTable(Rng& rng);  // low: may stand where cameras pass above it
// Office.
Item makeDesk(Rng& rng);  // with monitor(s), a tower and a chair in front
Item makeFilingCabinet(Rng& rng);
Item makeCupboard(Rng& rng);  // doors below, open shelves of binders above
Item makeBin(Rng& rng);
Item makeLowCabinet(Rng& rng);  // low
// Either room.
Item makeColumn(float radius, float height);
// A thin panel hung on the wall (picture, whiteboard): bottom edge at `bottomM` above the floor.
Item makeWallPanel(Rng& rng, float width, float height, float bottomM, const std::string& kind);
// Wall fixtures, `width` metres along the wall, lowest edge `bottomM` above the floor. Unlike
// a panel they stand out from the wall (up to kWallFixtureMaxDepthM), so their sides, undersides and the
// round things on them face along the wall and up or down: what ICP needs to see motion along a wall.
constexpr float kWallFixtureMaxDepthM = 0.32f;
Item makeWallShelf(Rng& rng, float width, float bottomM);      // a board on brackets with books, vases, boxes
Item makeWallCabinet(Rng& rng, float width, float bottomM);    // a hung cupboard with doors and things on top
Item makeFramedPicture(Rng& rng, float width, float bottomM);  // a deep frame around a recessed canvas

}  // namespace sb::synth
