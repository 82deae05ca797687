#pragma once
// Shared by the OpenCL tests: the device they run on (test_opencl_main.cpp skips the binary when there is
// none) and comparisons of device maps with the CPU backend's.

#include <cmath>
#include <cstddef>
#include <vector>

#include "kernels/common.h"
#include "pipeline/opencl/device.h"

namespace sb::test {

// The device the OpenCL tests use: the automatic choice (a GPU when there is one, else e.g. PoCL).
const opencl::DeviceInfo& openclTestDevice();

// Largest |a - b| over values where both are finite.
inline double maxAbsDifference(const std::vector<float>& a, const std::vector<float>& b) {
  double worst = 0;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) worst = std::fmax(worst, std::fabs(double(a[i]) - b[i]));
  return worst;
}

// Normal maps (3 floats per pixel, x = SB_INVALID_NORMAL when invalid): pixels whose validity differs, and the
// smallest dot product where both are valid.
struct NormalComparison {
  size_t pixels = 0, validityMismatches = 0, bothValid = 0;
  double minDot = 1.0, meanDot = 1.0;
};

inline NormalComparison compareNormals(const std::vector<float>& a, const std::vector<float>& b) {
  NormalComparison c;
  c.pixels = a.size() / 3;
  double sum = 0;
  for (size_t i = 0; i < c.pixels; ++i) {
    const bool va = a[3 * i] != SB_INVALID_NORMAL, vb = b[3 * i] != SB_INVALID_NORMAL;
    if (va != vb) ++c.validityMismatches;
    if (!va || !vb) continue;
    const double dot = double(a[3 * i]) * b[3 * i] + double(a[3 * i + 1]) * b[3 * i + 1] + double(a[3 * i + 2]) * b[3 * i + 2];
    c.minDot = std::fmin(c.minDot, dot);
    sum += dot;
    ++c.bothValid;
  }
  c.meanDot = c.bothValid ? sum / c.bothValid : 1.0;
  return c;
}

}  // namespace sb::test
