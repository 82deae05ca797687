#pragma once
// Hand-made views for the odometry tests: a structure matrix whose eigen-motions are the camera axes (basis
// identity: the twist's translation then rotation), each with its conditioning.

#include <initializer_list>

#include "pipeline/tracking_quality.h"

namespace sb::test {

// A view that fixes every motion with conditioning `c`, except those in `free` (0-5: tx ty tz rx ry rz).
inline TrackingQuality view(double c, std::initializer_list<int> free = {}) {
  TrackingQuality q;
  q.known = true;
  Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Constant(c);
  for (int i : free) d(i) = 1e-5;
  q.structure = d.asDiagonal();
  q.basis = Matrix6::Identity();
  q.conditioning = d.minCoeff();
  return q;
}

}  // namespace sb::test
