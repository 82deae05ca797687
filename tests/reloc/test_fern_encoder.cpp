// Fern codes: the same view gives the same code, another view a different one, a frame without depth none,
// and a view seen from a little farther (every depth larger by the same amount) nearly the same code.

#include <catch2/catch.hpp>

#include "reloc/fern_encoder.h"

namespace {

// A 160x120 view in millimetres: a floor ramp with a box whose place and size vary with `layout`.
sb::DepthRaw view(int layout, int offsetMm = 0) {
  sb::DepthRaw d(160, 120);
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x) {
      int mm = 3000 - 12 * y;
      const int bx = 20 + 37 * layout % 100, by = 10 + 23 * layout % 60;
      if (x >= bx && x < bx + 40 && y >= by && y < by + 35) mm = 1200 + 150 * (layout % 3);
      d(x, y) = static_cast<uint16_t>(mm + offsetMm);
    }
  return d;
}

}  // namespace

TEST_CASE("Fern codes tell views apart and ignore the distance of the whole view", "[reloc][fern]") {
  const sb::FernEncoder encoder(sb::FernParams{});
  const sb::FernCode a = encoder.encode(view(1), 0.001);
  REQUIRE(a.valid());
  CHECK(a.codes.size() == 500);
  CHECK(a.dissimilarity(encoder.encode(view(1), 0.001)) == 0.0);
  const double other = a.dissimilarity(encoder.encode(view(2), 0.001));
  const double farther = a.dissimilarity(encoder.encode(view(1, 150), 0.001));
  CHECK(other > 0.3);
  CHECK(farther < 0.05);
  CHECK(farther < other);
  // Same seed, same tests: codes of two encoders are comparable.
  CHECK(a.dissimilarity(sb::FernEncoder(sb::FernParams{}).encode(view(1), 0.001)) == 0.0);
}

TEST_CASE("A frame with too little depth has no fern code", "[reloc][fern]") {
  const sb::FernEncoder encoder(sb::FernParams{});
  sb::DepthRaw empty(160, 120);
  CHECK_FALSE(encoder.encode(empty, 0.001).valid());
  sb::DepthRaw sliver = view(1);
  for (int y = 0; y < 120; ++y)
    for (int x = 20; x < 160; ++x) sliver(x, y) = 0;  // only an eighth of the cells keep depth
  CHECK_FALSE(encoder.encode(sliver, 0.001).valid());
  const sb::FernCode none;
  CHECK(none.dissimilarity(encoder.encode(view(1), 0.001)) == 1.0);
}
