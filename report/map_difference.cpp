#include "report/map_difference.h"

#include <algorithm>
#include <cstdlib>

#include "core/error.h"

namespace sb::report {

namespace {

const Rgb8 kNeither{255, 255, 255}, kOnlyA{0, 114, 178}, kOnlyB{230, 159, 0};
const Rgb8 kEqual{230, 230, 230}, kFar{165, 0, 0};

uint8_t mix(uint8_t from, uint8_t to, double t) { return static_cast<uint8_t>(from + (to - from) * t + 0.5); }

// b sampled at a's pixel (x, y), nearest neighbour when the sizes differ.
uint8_t sample(const Image<uint8_t>& b, int x, int y, int width, int height) {
  const int bx = std::min(b.width() - 1, static_cast<int>((x + 0.5) * b.width() / width));
  const int by = std::min(b.height() - 1, static_cast<int>((y + 0.5) * b.height() / height));
  return b(bx, by);
}

}  // namespace

MapDifference compareMaps(const Image<uint8_t>& a, const Image<uint8_t>& b) {
  if (a.empty() || b.empty()) throw Error("cannot compare maps: an image is empty");
  MapDifference d;
  d.resampled = a.width() != b.width() || a.height() != b.height();
  d.image.resize(a.width(), a.height());
  size_t onlyA = 0, onlyB = 0, different = 0;
  double sum = 0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) {
      const int va = a(x, y), vb = d.resampled ? sample(b, x, y, a.width(), a.height()) : b(x, y);
      Rgb8& out = d.image(x, y);
      if (va == 0 && vb == 0) {
        out = kNeither;
      } else if (vb == 0) {
        out = kOnlyA;
        ++onlyA;
      } else if (va == 0) {
        out = kOnlyB;
        ++onlyB;
      } else {
        const int diff = std::abs(va - vb);
        ++d.bothPixels;
        sum += diff;
        different += diff > kDifferenceThreshold;
        const double t = std::min(1.0, static_cast<double>(diff) / kDifferenceSaturation);
        out = {mix(kEqual.r, kFar.r, t), mix(kEqual.g, kFar.g, t), mix(kEqual.b, kFar.b, t)};
      }
    }
  const double pixels = static_cast<double>(a.size());
  d.fractionOnlyA = static_cast<double>(onlyA) / pixels;
  d.fractionOnlyB = static_cast<double>(onlyB) / pixels;
  if (d.bothPixels > 0) {
    d.meanAbsDifference = sum / static_cast<double>(d.bothPixels);
    d.fractionDifferent = static_cast<double>(different) / static_cast<double>(d.bothPixels);
  }
  return d;
}

}  // namespace sb::report
