#pragma once
// Host side of ICP: solving the reduced 6x6 normal equations and applying the update.

#include <Eigen/Geometry>

#include "pipeline/backend.h"

namespace sb {

using Twist = Eigen::Matrix<double, 6, 1>;  // (translation m, rotation rad) in the world (volume) frame

// Minimum inliers for a solve (6 unknowns).
constexpr double kMinIcpInliers = 6;
// Directions whose eigenvalue is below this fraction of the largest are not updated (a plane constrains only
// 3 of the 6 degrees of freedom; like SLAMBench's truncated SVD solve).
constexpr double kIcpEigenCutoff = 1e-6;

// Solves J^T J x = J^T e from the reduced sums. Returns false (x = 0) when there are too few inliers or the
// system is not finite.
bool solveIcpUpdate(const TrackSums& sums, Twist& x);

// The rigid motion exp(x): rotation by the axis-angle x.tail<3>, translation V * x.head<3>.
Eigen::Isometry3d twistToTransform(const Twist& x);

}  // namespace sb
