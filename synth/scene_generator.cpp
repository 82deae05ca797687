#include "synth/scene_generator.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "synth/furniture.h"

namespace sb::synth {

namespace {

// Plan-view rectangle in world x (min, max) and z (min, max), metres.
struct Rect {
  float x0, x1, z0, z1;
  bool overlaps(const Rect& o, float gap = 0.f) const {
    return x0 < o.x1 + gap && o.x0 < x1 + gap && z0 < o.z1 + gap && o.z0 < z1 + gap;
  }
};

// Where the cameras go: the ICL-NUIM trajectories' positions span x [-1.07, 1.07], z [-2.68, 2.42]; this
// rectangle adds at least 0.33 m of clearance. Only low furniture stands inside it.
constexpr Rect kCameraSpace{-1.55f, 1.4f, -3.0f, 2.75f};
// Inside kCameraSpace, a spot at least 0.29 m from every ICL-NUIM camera position (livingroom3 loops around).
constexpr Rect kIsland{-0.1f, 0.3f, 0.7f, 1.4f};
constexpr float kLowMaxHeightM = 0.5f;     // furniture this low may stand in kCameraSpace (cameras are >= 1 m up)
constexpr float kBlankWallM = 1.3f;        // every wall keeps a blank stretch this long
constexpr float kWallGapM = 0.02f;         // furniture stands this far off the wall
constexpr float kItemGapM = 0.05f;         // minimum plan-view gap between pieces of furniture
constexpr float kMaxStripDepthM = 1.2f;    // furniture along a wall reaches at most this far into the room
constexpr float kYawJitterRad = 0.06f;     // furniture is not perfectly square to the wall

struct RoomSpec {
  Eigen::Vector3f min, max;  // interior, world; floor at max.y()
  std::vector<ItemBuilder> wallItems;
  ItemBuilder eastAnchor, westAnchor;  // tried first on the long walls, so every room has its key pieces
  std::vector<ItemBuilder> lowItems;  // placed in kCameraSpace
  const char* panelKind;              // picture / whiteboard
  float panelMinWidth, panelMaxWidth, panelMinHeight, panelMaxHeight;
};

RoomSpec livingRoomSpec() {
  return {Eigen::Vector3f(-2.5f, -1.55f, -3.5f), Eigen::Vector3f(2.5f, 1.25f, 3.3f),
          {makeSofa, makeSofa, makeArmchair, makeBookshelf, makeBookshelf, makeTvStand, makeSideboard,
           makeSideTable, makeFloorLamp, makePlant, makeBoxStack},
          makeSofa, makeTvStand,
          {makeCoffeeTable},
          "picture", 0.4f, 1.0f, 0.3f, 0.7f};
}

RoomSpec officeSpec() {
  return {Eigen::Vector3f(-2.55f, -1.45f, -3.55f), Eigen::Vector3f(2.55f, 1.25f, 3.35f),
          {makeDesk, makeDesk, makeDesk, makeFilingCabinet, makeCupboard, makeBookshelf, makeBin, makePlant,
           makeBoxStack},
          makeDesk, makeDesk,
          {makeLowCabinet},
          "whiteboard", 0.9f, 1.8f, 0.6f, 1.1f};
}

// FNV-1a: a string hash that is the same on every platform (std::hash is not).
uint64_t hashName(const std::string& name) {
  uint64_t h = 0xCBF29CE484222325ull;
  for (unsigned char c : name) h = (h ^ c) * 0x100000001B3ull;
  return h;
}

class Placer {
 public:
  Placer(Scene& scene, float floorY) : scene_(scene), floorY_(floorY) {}

  enum class Mode {
    Floor,     // must stay in the room, off other furniture and (unless low) out of the camera space
    Anchored,  // placed as given (the column in the island); later furniture keeps off it
    OnWall,    // placed as given, takes no floor space (pictures, whiteboards)
  };

  // Places `item` with its back-centre at plan point (x, z), its depth axis along `inward` (unit, plan).
  // Returns false (placing nothing) when a Floor item does not fit.
  bool place(const Item& item, float x, float z, const Eigen::Vector2f& inward, Mode mode = Mode::Floor) {
    const Eigen::Vector3f n(inward.x(), 0.f, inward.y()), u(inward.y(), 0.f, -inward.x());
    Eigen::Matrix3f R;
    R << u, Eigen::Vector3f::UnitY(), n;
    Rect fp{1e9f, -1e9f, 1e9f, -1e9f};
    for (float sx : {-0.5f, 0.5f}) {
      for (float sz : {0.f, 1.f}) {
        const Eigen::Vector3f c = R * Eigen::Vector3f(sx * item.width, 0.f, sz * item.depth);
        fp = {std::min(fp.x0, x + c.x()), std::max(fp.x1, x + c.x()), std::min(fp.z0, z + c.z()),
              std::max(fp.z1, z + c.z())};
      }
    }
    if (mode == Mode::Floor) {
      const Eigen::Vector3f& lo = scene_.roomMin;
      const Eigen::Vector3f& hi = scene_.roomMax;
      if (fp.x0 < lo.x() || fp.x1 > hi.x() || fp.z0 < lo.z() || fp.z1 > hi.z()) return false;
      if (item.height > kLowMaxHeightM && fp.overlaps(kCameraSpace)) return false;
      for (const auto& footprint : footprints_) {
        if (fp.overlaps(footprint.first, kItemGapM)) return false;
      }
    }
    if (mode != Mode::OnWall) footprints_.push_back({fp, item.height});
    const Eigen::Vector3f origin(x, floorY_, z);
    for (Primitive p : item.parts) {
      p.center = origin + R * p.center;
      p.rotation = R * p.rotation;
      scene_.primitives.push_back(p);
    }
    return true;
  }

  // Keeps floor furniture (and panels, see heightUnder) out of `r`.
  void reserve(const Rect& r) { footprints_.push_back({r, std::numeric_limits<float>::infinity()}); }

  // Height of the tallest furniture whose footprint overlaps `r` (0 if none).
  float heightUnder(const Rect& r) const {
    float h = 0.f;
    for (const auto& [fp, height] : footprints_) {
      if (fp.overlaps(r, kItemGapM)) h = std::max(h, height);
    }
    return h;
  }

 private:
  Scene& scene_;
  float floorY_;
  std::vector<std::pair<Rect, float>> footprints_;  // plan rectangle, height (m)
};

struct Wall {
  Eigen::Vector2f start;   // plan corner where the wall starts (x, z)
  Eigen::Vector2f along;   // unit plan direction along the wall
  Eigen::Vector2f inward;  // unit plan normal into the room
  float length;            // metres
  float depth;             // free depth between the wall and the camera space, metres
  bool blankAtEnd;         // keep the blank stretch at a corner: cameras face the middle of this wall closely
};

std::vector<Wall> wallsOf(const RoomSpec& spec) {
  const float x0 = spec.min.x(), x1 = spec.max.x(), z0 = spec.min.z(), z1 = spec.max.z();
  auto strip = [](float d) { return std::min(d, kMaxStripDepthM); };
  return {
      {{x0, z1}, {0.f, -1.f}, {1.f, 0.f}, z1 - z0, strip(kCameraSpace.x0 - x0), false},   // west
      {{x1, z0}, {0.f, 1.f}, {-1.f, 0.f}, z1 - z0, strip(x1 - kCameraSpace.x1), false},   // east
      {{x0, z0}, {1.f, 0.f}, {0.f, 1.f}, x1 - x0, strip(kCameraSpace.z0 - z0), true},     // south (-z)
      {{x1, z1}, {-1.f, 0.f}, {0.f, -1.f}, x1 - x0, strip(z1 - kCameraSpace.z1), true},   // north (+z)
  };
}

Eigen::Vector2f rotated(const Eigen::Vector2f& v, float angle) {
  const float c = std::cos(angle), s = std::sin(angle);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

Rect planRect(const Wall& wall, float from, float to, float depth) {
  const Eigen::Vector2f a = wall.start + from * wall.along, b = wall.start + to * wall.along;
  const Eigen::Vector2f c = a + depth * wall.inward;
  return {std::min({a.x(), b.x(), c.x()}), std::max({a.x(), b.x(), c.x()}), std::min({a.y(), b.y(), c.y()}),
          std::max({a.y(), b.y(), c.y()})};
}

// Where along the wall its blank stretch starts, metres.
float blankStartOf(const Wall& wall, Rng& rng) {
  constexpr float kCornerSlackM = 0.2f;
  if (!wall.blankAtEnd) return rng.uniform(0.f, wall.length - kBlankWallM);
  return rng.chance(0.5) ? rng.uniform(0.f, kCornerSlackM) : wall.length - kBlankWallM - rng.uniform(0.f, kCornerSlackM);
}

// Furniture along the wall and one or two panels above it; returns the panels' spans along the wall (metres).
std::vector<Eigen::Vector2f> furnishWall(const Wall& wall, float blankStart, const RoomSpec& spec,
                                         ItemBuilder anchor, Rng& rng, Placer& placer) {
  const float blankEnd = blankStart + kBlankWallM;
  float pos = rng.uniform(0.f, 0.4f);
  constexpr int kTriesPerSlot = 8;
  while (pos < wall.length) {
    bool placed = false;
    for (int attempt = 0; attempt < kTriesPerSlot && !placed; ++attempt) {
      const Item item = anchor ? anchor(rng) : spec.wallItems[rng.index(static_cast<int>(spec.wallItems.size()))](rng);
      if (item.depth + kWallGapM > wall.depth) continue;
      const float end = pos + item.width;
      if (end > wall.length || (pos < blankEnd && end > blankStart)) continue;
      const Eigen::Vector2f p = wall.start + (pos + item.width / 2) * wall.along + kWallGapM * wall.inward;
      placed = placer.place(item, p.x(), p.y(), rotated(wall.inward, rng.uniform(-kYawJitterRad, kYawJitterRad)));
      if (placed) pos = end;
    }
    if (placed) anchor = nullptr;
    pos += placed ? rng.uniform(0.1f, 0.6f) : rng.uniform(0.3f, 0.8f);
  }
  // Panels on the wall above low furniture, away from the blank stretch.
  std::vector<Eigen::Vector2f> spans;
  const int panels = 1 + rng.index(2);
  for (int i = 0; i < panels; ++i) {
    const float w = rng.uniform(spec.panelMinWidth, spec.panelMaxWidth);
    const float h = rng.uniform(spec.panelMinHeight, spec.panelMaxHeight);
    const float bottom = rng.uniform(1.0f, 1.3f);
    const float at = rng.uniform(0.1f, wall.length - w - 0.1f);
    if (at < blankEnd && at + w > blankStart) continue;
    constexpr float kPanelClearanceM = 0.1f;
    if (placer.heightUnder(planRect(wall, at, at + w, kPanelClearanceM)) > bottom) continue;
    const Item panel = makeWallPanel(rng, w, h, bottom, spec.panelKind);
    const Eigen::Vector2f p = wall.start + (at + w / 2) * wall.along;
    placer.place(panel, p.x(), p.y(), wall.inward, Placer::Mode::OnWall);
    spans.emplace_back(at, at + w);
  }
  return spans;
}

// Fixtures hung on the wall one after another along it: framed pictures, shelves and hung cabinets, at
// heights from below to above eye level, so that their undersides, tops and sides are seen. None on the blank
// stretch or over the panels (`panels`: spans along the wall, metres), none reaching into the camera space;
// raised over the furniture below them, left out where that leaves no room below the ceiling. Run after every
// wall is furnished (the side walls' furniture reaches into the corners).
void decorateWall(const Wall& wall, float blankStart, const std::vector<Eigen::Vector2f>& panels,
                  float roomHeight, Rng& rng, Placer& placer) {
  constexpr float kCornerGapM = 0.35f;                 // fixtures keep this far from the corners
  constexpr float kMinGapM = 0.05f, kMaxGapM = 0.35f;  // between neighbouring fixtures
  // Lowest edge above the floor, before furniture: shelves and cabinets below or above the cameras' eye level
  // (about 1.1-1.6 m), so that their tops or undersides are seen rather than their edges; pictures at any
  // height.
  constexpr float kLowBandM[2] = {0.85f, 1.0f}, kHighBandM[2] = {1.75f, 2.0f},
                  kPictureBandM[2] = {1.1f, 1.7f};
  constexpr float kOverFurnitureM = 0.12f;  // lowest edge above the furniture below
  constexpr float kCeilingGapM = 0.05f;     // top (ornaments included) below the ceiling
  constexpr float kClearanceM = 0.05f;      // in front of a fixture, over furniture below
  constexpr float kSkipM = 0.1f;            // moved on this far when a fixture does not fit
  const float blankEnd = blankStart + kBlankWallM;
  float at = kCornerGapM + rng.uniform(0.f, kMaxGapM);
  while (at < wall.length - kCornerGapM) {
    enum Kind { kPicture, kShelf, kCabinet };
    constexpr Kind kKinds[] = {kPicture, kShelf, kShelf, kCabinet};  // shelves twice as often
    constexpr float kWidthsM[][2] = {{0.3f, 0.8f}, {0.6f, 1.2f}, {0.5f, 1.f}};
    const Kind kind = kKinds[rng.index(4)];
    const float w = rng.uniform(kWidthsM[kind][0], kWidthsM[kind][1]);
    const float* band = kind == kPicture ? kPictureBandM : rng.chance(0.5) ? kLowBandM : kHighBandM;
    float bottom = rng.uniform(band[0], band[1]);
    const bool onPanel = std::any_of(panels.begin(), panels.end(), [&](const Eigen::Vector2f& span) {
      return at < span.y() + kMinGapM && at + w + kMinGapM > span.x();
    });
    if (at + w > wall.length - kCornerGapM || (at < blankEnd && at + w > blankStart) || onPanel) {
      at += kSkipM;
      continue;
    }
    const Rect space = planRect(wall, at, at + w, kWallFixtureMaxDepthM + kClearanceM);
    bottom = std::max(bottom, placer.heightUnder(space) + kOverFurnitureM);
    Item item;
    switch (kind) {
      case kPicture:
        item = makeFramedPicture(rng, w, bottom);
        break;
      case kShelf:
        item = makeWallShelf(rng, w, bottom);
        break;
      case kCabinet:
        item = makeWallCabinet(rng, w, bottom);
        break;
    }
    if (space.overlaps(kCameraSpace) || item.height > roomHeight - kCeilingGapM) {
      at += kSkipM;
      continue;
    }
    const Eigen::Vector2f p = wall.start + (at + w / 2) * wall.along;
    placer.place(item, p.x(), p.y(), wall.inward, Placer::Mode::OnWall);
    at += w + rng.uniform(kMinGapM, kMaxGapM);
  }
}

}  // namespace

const std::vector<std::string>& sceneNames() {
  static const std::vector<std::string> names{"livingroom", "office"};
  return names;
}

Scene generateScene(const std::string& name, uint64_t seed) {
  RoomSpec spec;
  if (name == "livingroom") {
    spec = livingRoomSpec();
  } else if (name == "office") {
    spec = officeSpec();
  } else {
    throw Error("synth: unknown scene '" + name + "'; use one of: livingroom, office");
  }
  Scene scene;
  scene.name = name;
  scene.seed = seed;
  scene.hasRoom = true;
  scene.roomMin = spec.min;
  scene.roomMax = spec.max;
  Primitive room;
  room.shape = Shape::RoomBox;
  room.center = 0.5f * (spec.min + spec.max);
  room.halfExtents = 0.5f * (spec.max - spec.min);
  room.label = "room";
  scene.primitives.push_back(room);

  Rng rng(seed * 0x2545F4914F6CDD1Dull + hashName(name));
  const float floorY = spec.max.y();
  const float roomHeight = spec.max.y() - spec.min.y();
  Placer placer(scene, floorY);
  // The column first: it anchors the layout the livingroom3 loop walks around.
  const float columnR = 0.5f * std::min(kIsland.x1 - kIsland.x0, kIsland.z1 - kIsland.z0) - 0.01f;
  const float columnX = 0.5f * (kIsland.x0 + kIsland.x1), columnZ = 0.5f * (kIsland.z0 + kIsland.z1);
  placer.place(makeColumn(columnR, roomHeight), columnX, columnZ - columnR, {0.f, 1.f}, Placer::Mode::Anchored);

  std::vector<Wall> walls = wallsOf(spec);
  const ItemBuilder anchors[] = {spec.westAnchor, spec.eastAnchor, nullptr, nullptr};  // in wallsOf order
  std::vector<float> blankStarts;
  for (const Wall& wall : walls) {  // reserve every blank stretch first: furniture of the side walls reaches corners
    const float start = blankStartOf(wall, rng);
    blankStarts.push_back(start);
    placer.reserve(planRect(wall, start, start + kBlankWallM, wall.depth));
    scene.blankWalls.push_back(
        {wall.start + start * wall.along, wall.start + (start + kBlankWallM) * wall.along, wall.inward, wall.depth});
  }
  std::vector<std::vector<Eigen::Vector2f>> panels;
  for (size_t w = 0; w < walls.size(); ++w)
    panels.push_back(furnishWall(walls[w], blankStarts[w], spec, anchors[w], rng, placer));

  // One or two low pieces in the camera space, south of the column.
  const int lowCount = 1 + rng.index(2);
  constexpr int kLowTries = 20;
  for (int i = 0, tries = 0; i < lowCount && tries < kLowTries; ++tries) {
    const Item item = spec.lowItems[rng.index(static_cast<int>(spec.lowItems.size()))](rng);
    const float x = rng.uniform(kCameraSpace.x0 + 0.5f, kCameraSpace.x1 - 0.5f);
    const float z = rng.uniform(kCameraSpace.z0 + 0.8f, kIsland.z0 - 1.0f);
    if (placer.place(item, x, z, rotated({0.f, 1.f}, rng.uniform(-0.5f, 0.5f)))) ++i;
  }
  // Wall fixtures last, so the layout above is the same as before they were added.
  for (size_t w = 0; w < walls.size(); ++w)
    decorateWall(walls[w], blankStarts[w], panels[w], roomHeight, rng, placer);
  return scene;
}

}  // namespace sb::synth
