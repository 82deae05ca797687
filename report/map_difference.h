#pragma once
// Difference of two rendered maps (grey shaded raycasts, 0 = no surface) as a colour image and statistics.

#include "core/image.h"
#include "core/png_io.h"

namespace sb::report {

struct MapDifference {
  Image<Rgb8> image;  // light grey (equal) to dark red (>= kSaturation levels apart); blue / orange where only
                      // a / only b sees a surface; white where neither does
  bool resampled = false;  // b had another size and was resampled (nearest) to a's
  double meanAbsDifference = 0;    // grey levels, over pixels where both see a surface
  double fractionDifferent = 0;    // of those pixels, share differing by more than kThreshold levels
  double fractionOnlyA = 0, fractionOnlyB = 0;  // of all pixels
  size_t bothPixels = 0;
};

constexpr int kDifferenceThreshold = 16;   // grey levels counted as "different"
constexpr int kDifferenceSaturation = 64;  // grey levels shown at full red

// Throws sb::Error if either image is empty.
MapDifference compareMaps(const Image<uint8_t>& a, const Image<uint8_t>& b);

}  // namespace sb::report
