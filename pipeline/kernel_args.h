#pragma once
// Conversions from host types (Eigen, sb::Intrinsics) to the plain kernel argument structs of
// kernels/common.h. Shared by every backend.

#include <Eigen/Core>

#include "core/intrinsics.h"
#include "kernels/common.h"

namespace sb {

// The top 3x4 of a transform or a 3x4 projection, row-major.
template <typename Derived>
SbMat34 toMat34(const Eigen::MatrixBase<Derived>& m) {
  SbMat34 out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) out.m[4 * r + c] = static_cast<float>(m(r, c));
  return out;
}

inline SbCamera toCamera(const Intrinsics& k) { return SbCamera{k.fx, k.fy, k.cx, k.cy}; }

// K as a 3x3 matrix (pixels).
inline Eigen::Matrix3f cameraMatrix(const Intrinsics& k) {
  Eigen::Matrix3f K;
  K << k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1;
  return K;
}

}  // namespace sb
