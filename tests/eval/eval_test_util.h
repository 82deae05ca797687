#pragma once
// Trajectory builders for the eval tests, and an independent ATE (Horn's quaternion method) as oracle.

#include <Eigen/Geometry>

#include "core/trajectory.h"

namespace sb::test {

// A pose from a position and a rotation given as axis-angle (radians about the unit axis).
TimedPose makePose(double timestamp, const Eigen::Vector3d& position, const Eigen::Vector3d& axis = {0, 0, 1},
                   double angleRad = 0.0);

// A handheld-like trajectory: `n` poses at `rateHz`, positions on a tilted helix, rotation changing smoothly.
Trajectory helixTrajectory(size_t n, double rateHz = 30.0);

// Every pose left-multiplied by T (a change of world frame).
Trajectory transformed(const Trajectory& t, const Eigen::Isometry3d& T);

// ATE RMSE (m) after Horn's closed-form alignment computed with unit quaternions (the eigenvector of the
// largest eigenvalue of Horn's 4x4 matrix N), for poses already paired index by index. Also returns the
// alignment (estimate onto ground truth) in `alignment`.
double hornQuaternionRmse(const Trajectory& estimate, const Trajectory& groundTruth,
                          Eigen::Isometry3d* alignment = nullptr);

}  // namespace sb::test
