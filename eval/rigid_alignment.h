#pragma once
// Closed-form rigid alignment of two point sets (Horn 1987 / Umeyama 1991 without scale): the rotation and
// translation that minimise sum |R * from_i + t - to_i|^2, with the reflection case handled.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace sb {

// Relative size (to the largest singular value of the centred points) below which a direction counts as
// absent: points whose second singular value is smaller are collinear, and the rotation about that line is
// undefined.
constexpr double kCollinearRelativeTolerance = 1e-9;
// Spread (metres, RMS distance to the centroid) below which all points count as identical.
constexpr double kIdenticalSpreadM = 1e-12;

// `from` and `to` are 3xN with the same N (N >= 3), column i of one corresponding to column i of the other.
// `fromName` / `toName` name the point sets in error messages. Throws sb::Error when the sizes differ,
// N < 3, or either set (or their cross-covariance) is degenerate: all points identical or collinear.
Eigen::Isometry3d alignRigid(const Eigen::Matrix3Xd& from, const Eigen::Matrix3Xd& to,
                             const char* fromName = "estimate", const char* toName = "ground truth");

}  // namespace sb
