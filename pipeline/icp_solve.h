#pragma once
// Host side of ICP: solving the reduced 6x6 normal equations and applying the update.

#include <Eigen/Geometry>

#include "pipeline/backend.h"

namespace sb {

using Twist = Eigen::Matrix<double, 6, 1>;  // (translation m, rotation rad) in the world (volume) frame
using Matrix6 = Eigen::Matrix<double, 6, 6>;

// Minimum inliers for a solve (6 unknowns).
constexpr double kMinIcpInliers = 6;
// Directions whose eigenvalue is below this fraction of the largest are not updated (a plane constrains only
// 3 of the 6 degrees of freedom; like SLAMBench's truncated SVD solve).
constexpr double kIcpEigenCutoff = 1e-6;

// A planar base's physics as a prior on the pose ICP solves for (IcpStart::prior): a wheeled base on its floor keeps
// the camera's height along `up` and its tilt (the rotation about the axes square to `up`) whatever its wheels
// read. The solve is pulled towards `target`'s height and tilt as firmly as a view whose structure fixed those
// motions with conditioning `conditioning` would (tracking_quality.h: per inlier, in the normalised basis, where a
// rotation weighs as the displacement it makes at the view's depth). Along a motion the view fixes far more firmly
// than that the view wins; along one it leaves free (a wall ahead leaves the height free) the prior holds, inside
// the solve, so the pose the frame is fused at is one the view fits (a correction after the solve is not: held off
// the view's own fit, the frames bent the map towards the view's error).
struct PlanarPrior {
  Eigen::Isometry3d target = Eigen::Isometry3d::Identity();  // T_camera_to_world whose height and tilt are kept
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();             // the floor's up, world frame, unit
  double conditioning = 0.0;                                 // its weight (0: none)
};

// Solves J^T J x = J^T e from the reduced sums. Returns false (x = 0) when there are too few inliers or the
// system is not finite.
bool solveIcpUpdate(const TrackSums& sums, Twist& x);

// The same, except that motions the view leaves free stay where they are: in the basis of
// tracking_quality.h (rotations about the camera centre `T_camera_to_world`, scaled to weigh like
// translations, per inlier), the update along every eigenvector whose eigenvalue is below `holdBelow` is 0.
// Along a motion that the geometry does not fix (sliding along a blank wall) ICP's update is the noise
// divided by a near-zero eigenvalue; holding it keeps the start pose there. With `prior` (when its conditioning
// is positive) the solve also weighs the planar prior (PlanarPrior) in the same basis. holdBelow <= 0 and no prior:
// solveIcpUpdate.
bool solveIcpUpdateHolding(const TrackSums& sums, const Eigen::Isometry3d& T_camera_to_world, double holdBelow,
                           Twist& x, const PlanarPrior* prior = nullptr);

// The planar prior's terms added to the normal equations in the motion basis (`An`, `bn` = T^T b / inliers, `T`
// from normalisedNormalMatrix) for a camera at `T_camera_to_world`: its height and tilt pulled towards the prior's.
void addPlanarPrior(const PlanarPrior& prior, const Eigen::Isometry3d& T_camera_to_world, const Matrix6& T,
                    Matrix6& An, Twist& bn);

// The reduced sums as J^T J (6x6) and J^T e.
void icpNormalEquations(const TrackSums& sums, Matrix6& A, Twist& b);

// The normal matrix in the motion basis of tracking_quality.h for a camera at `T_camera_to_world`:
// An = T^T A T / inliers, with twist x = T * x_n, where x_n has its rotations about the camera centre, scaled
// so that A's rotational block carries the trace of the translational one. False when either trace is not
// positive (no usable constraint).
bool normalisedNormalMatrix(const Matrix6& A, double inliers, const Eigen::Isometry3d& T_camera_to_world,
                            Matrix6& An, Matrix6& T);

// The rigid motion exp(x): rotation by the axis-angle x.tail<3>, translation V * x.head<3>.
Eigen::Isometry3d twistToTransform(const Twist& x);
// Its inverse, log(T), for rotations below pi.
Twist transformToTwist(const Eigen::Isometry3d& T);

}  // namespace sb
