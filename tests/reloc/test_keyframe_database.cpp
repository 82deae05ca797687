// The keyframe database: harvests only views unlike the stored ones, holds at most its capacity (the oldest
// goes), and returns the most alike keyframes first.

#include <catch2/catch.hpp>

#include "core/error.h"
#include "reloc/keyframe_database.h"

namespace {

// A code of 10 ferns whose first `ones` codes are 1, the rest 0.
sb::FernCode code(int ones) {
  sb::FernCode c;
  c.codes.assign(10, 0);
  for (int i = 0; i < ones && i < 10; ++i) c.codes[i] = 1;
  return c;
}

Eigen::Isometry3d at(double x) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation().x() = x;
  return t;
}

}  // namespace

TEST_CASE("Keyframes are harvested only from views unlike the stored ones", "[reloc][keyframes]") {
  sb::KeyframeDatabase db(10, 0.2);
  CHECK(db.harvest(code(0), at(0), 0));
  CHECK_FALSE(db.harvest(code(2), at(1), 1));  // 0.2 from code(0): not unlike enough
  CHECK(db.harvest(code(3), at(2), 2));
  CHECK_FALSE(db.harvest(sb::FernCode{}, at(3), 3));  // no code (no depth)
  CHECK(db.size() == 2);
  CHECK(db.memoryBytes() >= 2 * 10);

  const auto best = db.nearest(code(4), 5);
  REQUIRE(best.size() == 2);
  CHECK(best[0].keyframe->frame == 2);
  CHECK(best[0].dissimilarity == Approx(0.1));
  CHECK(best[1].keyframe->frame == 0);
  CHECK(db.nearest(code(4), 1).size() == 1);
  CHECK(db.nearest(sb::FernCode{}, 3).empty());
}

TEST_CASE("The keyframe database is bounded: the oldest keyframe goes", "[reloc][keyframes]") {
  sb::KeyframeDatabase db(2, 0.05);
  CHECK(db.harvest(code(0), at(0), 0));
  CHECK(db.harvest(code(5), at(1), 1));
  CHECK(db.harvest(code(10), at(2), 2));
  CHECK(db.size() == 2);
  const auto all = db.nearest(code(0), 5);
  REQUIRE(all.size() == 2);
  for (const auto& m : all) CHECK(m.keyframe->frame != 0);
  CHECK_THROWS_AS(sb::KeyframeDatabase(0, 0.1), sb::Error);
  CHECK_THROWS_AS(sb::KeyframeDatabase(1, 1.5), sb::Error);
}
