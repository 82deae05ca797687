#include "synth/furniture.h"

#include <algorithm>

namespace sb::synth {

namespace {

// Adds an axis-aligned box spanning x [x0, x1], heights [h0, h1] above the floor, z [z0, z1].
void addBox(Item& item, float x0, float x1, float h0, float h1, float z0, float z1, const std::string& part) {
  const Eigen::Vector3f center(0.5f * (x0 + x1), -0.5f * (h0 + h1), 0.5f * (z0 + z1));
  const Eigen::Vector3f size(x1 - x0, h1 - h0, z1 - z0);
  item.parts.push_back(makeBox(center, size, 0.f, item.kind + "." + part));
}

void addCylinder(Item& item, float x, float z, float radius, float h0, float h1, const std::string& part) {
  item.parts.push_back(makeVerticalCylinder(Eigen::Vector3f(x, -h0, z), radius, h1 - h0, item.kind + "." + part));
}

Item begin(const std::string& kind, float width, float depth, float height) {
  Item item;
  item.kind = kind;
  item.width = width;
  item.depth = depth;
  item.height = height;
  return item;
}

// A seat with back and arms (sofa, armchair).
Item makeSeat(const std::string& kind, float w, float d) {
  constexpr float kSeatH = 0.42f, kBackH = 0.85f, kBackD = 0.2f, kArmW = 0.18f, kArmH = 0.62f;
  Item item = begin(kind, w, d, kBackH);
  addBox(item, -w / 2 + kArmW, w / 2 - kArmW, 0.f, kSeatH, kBackD, d, "seat");
  addBox(item, -w / 2, w / 2, 0.f, kBackH, 0.f, kBackD, "back");
  addBox(item, -w / 2, -w / 2 + kArmW, 0.f, kArmH, kBackD, d, "arm");
  addBox(item, w / 2 - kArmW, w / 2, 0.f, kArmH, kBackD, d, "arm");
  return item;
}

// Open shelving with a back panel, sides and `shelves` boards, some holding books.
Item makeShelving(Rng& rng, const std::string& kind, float w, float d, float h, int shelves) {
  constexpr float kBoard = 0.025f;                          // board thickness, metres
  constexpr float kBookMinW = 0.05f, kBookMaxW = 0.3f;      // width of a book or box, metres
  constexpr float kBookMaxGapM = 0.1f;                      // gap after it, metres
  constexpr float kShelfEndSlackM = 0.2f;                   // no new book starts this near the side, metres
  constexpr double kFilledShare = 0.6;                      // share of slots holding something
  constexpr float kMinFill = 0.4f, kMaxFill = 0.85f;        // height as a share of the shelf gap
  constexpr float kMinDepthShare = 0.5f, kMaxDepthShare = 0.95f;
  Item item = begin(kind, w, d, h);
  addBox(item, -w / 2, w / 2, 0.f, h, 0.f, kBoard, "back");
  addBox(item, -w / 2, -w / 2 + kBoard, 0.f, h, 0.f, d, "side");
  addBox(item, w / 2 - kBoard, w / 2, 0.f, h, 0.f, d, "side");
  const float gap = h / shelves;
  for (int s = 0; s <= shelves; ++s) {
    const float y = std::min(s * gap, h - kBoard);
    addBox(item, -w / 2 + kBoard, w / 2 - kBoard, y, y + kBoard, 0.f, d, "board");
    if (s == shelves) break;
    float x = -w / 2 + kBoard;
    while (x < w / 2 - kShelfEndSlackM) {  // books and boxes of random widths, leaving gaps
      const float bw = rng.uniform(kBookMinW, kBookMaxW);
      if (x + bw > w / 2 - kBoard) break;
      if (rng.chance(kFilledShare)) {
        addBox(item, x, x + bw, y + kBoard, y + kBoard + rng.uniform(kMinFill, kMaxFill) * (gap - kBoard), kBoard,
               rng.uniform(kMinDepthShare, kMaxDepthShare) * d, "book");
      }
      x += bw + rng.uniform(0.f, kBookMaxGapM);
    }
  }
  return item;
}

}  // namespace

Item makeSofa(Rng& rng) { return makeSeat("sofa", rng.uniform(1.6f, 2.2f), rng.uniform(0.8f, 0.9f)); }

Item makeArmchair(Rng& rng) { return makeSeat("armchair", rng.uniform(0.8f, 0.95f), 0.8f); }

Item makeBookshelf(Rng& rng) {
  return makeShelving(rng, "bookshelf", rng.uniform(0.8f, 1.2f), rng.uniform(0.28f, 0.3f), rng.uniform(1.6f, 2.0f),
                      4 + rng.index(2));
}

Item makeTvStand(Rng& rng) {
  const float w = rng.uniform(1.2f, 1.6f), d = 0.4f, h = 0.5f;
  const float tvW = rng.uniform(0.9f, 1.2f), tvH = 0.56f * tvW;
  Item item = begin("tv", w, d, h + 0.05f + tvH);
  addBox(item, -w / 2, w / 2, 0.f, h, 0.f, d, "stand");
  addBox(item, -0.15f, 0.15f, h, h + 0.02f, 0.1f, 0.3f, "foot");
  addBox(item, -0.03f, 0.03f, h, h + 0.1f, 0.18f, 0.22f, "neck");
  addBox(item, -tvW / 2, tvW / 2, h + 0.05f, h + 0.05f + tvH, 0.15f, 0.22f, "screen");
  return item;
}

Item makeSideboard(Rng& rng) {
  const float w = rng.uniform(1.0f, 1.6f), d = 0.45f, h = rng.uniform(0.75f, 0.9f);
  Item item = begin("sideboard", w, d, h);
  addBox(item, -w / 2, w / 2, 0.1f, h - 0.03f, 0.f, d - 0.02f, "body");
  addBox(item, -w / 2 - 0.01f, w / 2 + 0.01f, h - 0.03f, h, 0.f, d, "top");
  addBox(item, -w / 2, -w / 2 + 0.05f, 0.f, 0.1f, 0.05f, d - 0.07f, "foot");
  addBox(item, w / 2 - 0.05f, w / 2, 0.f, 0.1f, 0.05f, d - 0.07f, "foot");
  if (rng.chance(0.7)) addCylinder(item, rng.uniform(-w / 3, w / 3), d / 2, 0.08f, h, h + 0.3f, "vase");
  return item;
}

Item makeSideTable(Rng& rng) {
  const float r = rng.uniform(0.22f, 0.3f), h = rng.uniform(0.5f, 0.6f);
  Item item = begin("side_table", 2 * r, 2 * r, h);
  addCylinder(item, 0.f, r, r, h - 0.03f, h, "top");
  addCylinder(item, 0.f, r, 0.03f, 0.02f, h - 0.03f, "leg");
  addCylinder(item, 0.f, r, 0.6f * r, 0.f, 0.02f, "base");
  return item;
}

Item makeFloorLamp(Rng& rng) {
  const float h = rng.uniform(1.5f, 1.8f), shadeR = rng.uniform(0.18f, 0.25f);
  Item item = begin("floor_lamp", 2 * shadeR, 2 * shadeR, h);
  addCylinder(item, 0.f, shadeR, 0.15f, 0.f, 0.03f, "base");
  addCylinder(item, 0.f, shadeR, 0.015f, 0.03f, h - 0.3f, "pole");
  addCylinder(item, 0.f, shadeR, shadeR, h - 0.3f, h, "shade");
  return item;
}

Item makePlant(Rng& rng) {
  const float potR = rng.uniform(0.15f, 0.22f), potH = rng.uniform(0.3f, 0.45f);
  const float leafR = rng.uniform(0.25f, 0.35f), leafH = rng.uniform(0.5f, 0.9f);
  Item item = begin("plant", 2 * leafR, 2 * leafR, potH + leafH);
  addCylinder(item, 0.f, leafR, potR, 0.f, potH, "pot");
  addCylinder(item, 0.f, leafR, leafR, potH + 0.05f, potH + leafH, "leaves");
  return item;
}

Item makeBoxStack(Rng& rng) {
  Item item = begin("boxes", 0.7f, 0.6f, 0.f);
  float h = 0.f;
  const int count = 1 + rng.index(3);
  for (int i = 0; i < count; ++i) {
    const float s = rng.uniform(0.3f, 0.5f) * (1.f - 0.15f * i), bh = rng.uniform(0.2f, 0.4f);
    const Eigen::Vector3f c(rng.uniform(-0.05f, 0.05f), -(h + bh / 2), 0.3f + rng.uniform(-0.05f, 0.05f));
    item.parts.push_back(makeBox(c, Eigen::Vector3f(s, bh, s * 0.9f), rng.uniform(-0.4f, 0.4f), "boxes.box"));
    h += bh;
  }
  item.height = h;
  return item;
}

Item makeCoffeeTable(Rng& rng) {
  const float w = rng.uniform(0.9f, 1.2f), d = rng.uniform(0.5f, 0.6f), h = rng.uniform(0.38f, 0.45f);
  Item item = begin("coffee_table", w, d, h);
  addBox(item, -w / 2, w / 2, h - 0.04f, h, 0.f, d, "top");
  addBox(item, -w / 2 + 0.05f, w / 2 - 0.05f, 0.08f, 0.12f, 0.05f, d - 0.05f, "shelf");
  for (float x : {-w / 2 + 0.03f, w / 2 - 0.03f}) {
    for (float z : {0.03f, d - 0.03f}) addBox(item, x - 0.025f, x + 0.025f, 0.f, h - 0.04f, z - 0.025f, z + 0.025f, "leg");
  }
  return item;
}

Item makeDesk(Rng& rng) {
  const float w = rng.uniform(1.2f, 1.6f), d = rng.uniform(0.6f, 0.7f), h = 0.74f;
  constexpr float kChairHalf = 0.24f, kSeatH = 0.46f;
  Item item = begin("desk", w, d + 0.25f, h + 0.5f);
  addBox(item, -w / 2, w / 2, h - 0.03f, h, 0.f, d, "top");
  addBox(item, -w / 2, -w / 2 + 0.03f, 0.f, h - 0.03f, 0.f, d, "panel");
  addBox(item, w / 2 - 0.03f, w / 2, 0.f, h - 0.03f, 0.f, d, "panel");
  addBox(item, -w / 2 + 0.03f, w / 2 - 0.03f, 0.3f, h - 0.03f, 0.f, 0.02f, "modesty");
  const int monitors = 1 + rng.index(2);
  for (int m = 0; m < monitors; ++m) {
    const float mx = monitors == 1 ? rng.uniform(-0.2f, 0.2f) : (m == 0 ? -0.3f : 0.3f);
    addBox(item, mx - 0.1f, mx + 0.1f, h, h + 0.02f, 0.1f, 0.3f, "monitor_foot");
    addBox(item, mx - 0.02f, mx + 0.02f, h + 0.02f, h + 0.15f, 0.15f, 0.18f, "monitor_neck");
    addBox(item, mx - 0.28f, mx + 0.28f, h + 0.12f, h + 0.45f, 0.18f, 0.21f, "monitor");
  }
  addBox(item, -0.22f, 0.22f, h, h + 0.02f, 0.35f, 0.5f, "keyboard");
  const float towerX = rng.chance(0.5) ? -w / 2 + 0.2f : w / 2 - 0.2f;
  addBox(item, towerX - 0.1f, towerX + 0.1f, 0.f, 0.45f, 0.1f, 0.55f, "tower");
  // Office chair pulled up to the desk.
  const float cx = rng.uniform(-0.2f, 0.2f), cz = d + 0.25f - kChairHalf;
  addCylinder(item, cx, cz, 0.22f, 0.05f, 0.1f, "chair_base");
  addCylinder(item, cx, cz, 0.03f, 0.1f, kSeatH - 0.06f, "chair_column");
  addBox(item, cx - kChairHalf, cx + kChairHalf, kSeatH - 0.06f, kSeatH, cz - kChairHalf, cz + kChairHalf, "chair_seat");
  addBox(item, cx - 0.22f, cx + 0.22f, kSeatH + 0.1f, kSeatH + 0.55f, cz + kChairHalf - 0.05f, cz + kChairHalf,
         "chair_back");
  addBox(item, cx - 0.02f, cx + 0.02f, kSeatH, kSeatH + 0.1f, cz + kChairHalf - 0.04f, cz + kChairHalf - 0.01f,
         "chair_post");
  return item;
}

Item makeFilingCabinet(Rng& rng) {
  const int drawers = 2 + rng.index(3);
  const float w = 0.45f, d = 0.6f, h = 0.33f * drawers;
  Item item = begin("filing_cabinet", w, d, h);
  addBox(item, -w / 2, w / 2, 0.f, h, 0.f, d - 0.02f, "body");
  for (int i = 0; i < drawers; ++i) {
    addBox(item, -w / 2 + 0.02f, w / 2 - 0.02f, i * 0.33f + 0.02f, (i + 1) * 0.33f - 0.02f, d - 0.02f, d, "front");
  }
  return item;
}

Item makeCupboard(Rng& rng) {
  // Doors below, open shelves of binders above (their pattern fixed, so the random draws are as for a closed
  // one).
  constexpr float kDoorsH = 0.9f, kBoard = 0.025f, kBinderW = 0.07f;
  constexpr float kBinderShare[] = {0.85f, 0.7f, 0.8f, 0.6f, 0.9f};  // of the shelf gap, cycling
  const float w = rng.uniform(0.8f, 1.0f), d = 0.45f, h = rng.uniform(1.8f, 2.1f);
  Item item = begin("cupboard", w, d, h);
  addBox(item, -w / 2, w / 2, 0.f, kDoorsH, 0.f, d - 0.02f, "body");
  addBox(item, -w / 2 + 0.01f, -0.005f, 0.05f, kDoorsH - 0.02f, d - 0.02f, d, "door");
  addBox(item, 0.005f, w / 2 - 0.01f, 0.05f, kDoorsH - 0.02f, d - 0.02f, d, "door");
  addBox(item, -w / 2, w / 2, kDoorsH, h, 0.f, kBoard, "back");
  addBox(item, -w / 2, -w / 2 + kBoard, kDoorsH, h, 0.f, d - 0.02f, "side");
  addBox(item, w / 2 - kBoard, w / 2, kDoorsH, h, 0.f, d - 0.02f, "side");
  const int shelves = 3;
  const float gap = (h - kDoorsH) / shelves;
  for (int s = 0; s <= shelves; ++s) {
    const float y = std::min(kDoorsH + s * gap, h - kBoard);
    addBox(item, -w / 2 + kBoard, w / 2 - kBoard, y, y + kBoard, 0.f, d - 0.02f, "board");
    if (s == shelves) break;
    int i = s;  // binders from one side, fewer on each shelf up, so the row ends at a different place
    for (float x = -w / 2 + kBoard; x + kBinderW < w / 2 - kBoard - 0.15f * (s + 1); x += kBinderW, ++i) {
      const float share = kBinderShare[i % 5];
      addBox(item, x, x + kBinderW - 0.005f, y + kBoard, y + kBoard + share * (gap - kBoard), kBoard,
             (0.6f + 0.3f * share) * d, "binder");
    }
  }
  return item;
}

Item makeBin(Rng& rng) {
  const float r = rng.uniform(0.13f, 0.18f);
  Item item = begin("bin", 2 * r, 2 * r, 0.35f);
  addCylinder(item, 0.f, r, r, 0.f, 0.35f, "body");
  return item;
}

Item makeLowCabinet(Rng& rng) {
  const float w = rng.uniform(0.8f, 1.2f), d = 0.45f, h = rng.uniform(0.4f, 0.45f);
  Item item = begin("low_cabinet", w, d, h);
  addBox(item, -w / 2, w / 2, 0.f, h, 0.f, d, "body");
  if (rng.chance(0.5)) addBox(item, -0.2f, 0.2f, h, h + 0.05f, 0.05f, 0.35f, "tray");
  return item;
}

Item makeColumn(float radius, float height) {
  Item item = begin("column", 2 * radius, 2 * radius, height);
  addCylinder(item, 0.f, radius, radius, 0.f, height, "shaft");
  return item;
}

Item makeWallPanel(Rng& rng, float width, float height, float bottomM, const std::string& kind) {
  const float thickness = rng.uniform(0.02f, 0.04f);
  Item item = begin(kind, width, thickness, bottomM + height);
  addBox(item, -width / 2, width / 2, bottomM, bottomM + height, 0.f, thickness, "panel");
  return item;
}

namespace {

// Things standing on a board whose top is `topH` above the floor, spanning x [x0, x1], z [0, depth): books
// and boxes (axis-aligned and turned) and round vases, leaving gaps.
void addOrnaments(Rng& rng, Item& item, float x0, float x1, float topH, float depth, float maxHeightM) {
  constexpr float kMinGapM = 0.03f, kMaxGapM = 0.2f;
  float x = x0 + rng.uniform(0.f, kMaxGapM);
  while (true) {
    const int kind = rng.index(3);
    const float w = kind == 2 ? rng.uniform(0.06f, 0.14f) : rng.uniform(0.08f, 0.3f);
    if (x + w > x1) break;
    const float h = rng.uniform(0.35f, 1.f) * maxHeightM;
    if (kind == 0) {  // books / box against the back
      addBox(item, x, x + w, topH, topH + h, 0.01f, rng.uniform(0.5f, 0.9f) * depth, "book");
    } else if (kind == 1) {  // a box turned on the board
      const float s = std::min(w, 0.8f * depth);
      item.parts.push_back(makeBox(Eigen::Vector3f(x + w / 2, -(topH + h / 2), 0.5f * depth),
                                   Eigen::Vector3f(s, h, s), rng.uniform(0.3f, 1.2f), item.kind + ".box"));
    } else {  // a vase or jar
      addCylinder(item, x + w / 2, 0.5f * depth, std::min(w / 2, 0.4f * depth), topH, topH + h, "vase");
    }
    x += w + rng.uniform(kMinGapM, kMaxGapM);
  }
}

}  // namespace

Item makeWallShelf(Rng& rng, float width, float bottomM) {
  constexpr float kBoard = 0.03f, kBracketW = 0.03f, kBracketH = 0.15f;
  const float d = rng.uniform(0.22f, kWallFixtureMaxDepthM);
  const float top = bottomM + kBracketH + kBoard;
  Item item = begin("wall_shelf", width, d, top + 0.35f);
  addBox(item, -width / 2, width / 2, bottomM + kBracketH, top, 0.f, d, "board");
  for (float x : {-width / 2 + 0.08f, width / 2 - 0.08f - kBracketW})
    addBox(item, x, x + kBracketW, bottomM, bottomM + kBracketH, 0.f, 0.7f * d, "bracket");
  addOrnaments(rng, item, -width / 2, width / 2, top, d, 0.32f);
  return item;
}

Item makeWallCabinet(Rng& rng, float width, float bottomM) {
  const float d = rng.uniform(0.28f, kWallFixtureMaxDepthM), h = rng.uniform(0.4f, 0.6f);
  Item item = begin("wall_cabinet", width, d, bottomM + h + 0.3f);
  addBox(item, -width / 2, width / 2, bottomM, bottomM + h, 0.f, d - 0.02f, "body");
  addBox(item, -width / 2 + 0.01f, -0.005f, bottomM + 0.01f, bottomM + h - 0.01f, d - 0.02f, d, "door");
  addBox(item, 0.005f, width / 2 - 0.01f, bottomM + 0.01f, bottomM + h - 0.01f, d - 0.02f, d, "door");
  addOrnaments(rng, item, -width / 2, width / 2, bottomM + h, d - 0.02f, 0.28f);
  return item;
}

Item makeFramedPicture(Rng& rng, float width, float bottomM) {
  const float h = rng.uniform(0.35f, 0.7f), frameW = rng.uniform(0.05f, 0.09f),
              frameD = rng.uniform(0.05f, 0.08f);
  Item item = begin("picture", width, frameD, bottomM + h);
  addBox(item, -width / 2, width / 2, bottomM, bottomM + frameW, 0.f, frameD, "frame");
  addBox(item, -width / 2, width / 2, bottomM + h - frameW, bottomM + h, 0.f, frameD, "frame");
  addBox(item, -width / 2, -width / 2 + frameW, bottomM + frameW, bottomM + h - frameW, 0.f, frameD, "frame");
  addBox(item, width / 2 - frameW, width / 2, bottomM + frameW, bottomM + h - frameW, 0.f, frameD, "frame");
  addBox(item, -width / 2 + frameW, width / 2 - frameW, bottomM + frameW, bottomM + h - frameW, 0.f, 0.015f,
         "canvas");
  return item;
}

}  // namespace sb::synth
