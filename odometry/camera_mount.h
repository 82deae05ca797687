#pragma once
// A camera mount "x y z qx qy qz qw" (the camera's optical frame in the base frame: metres, unit quaternion),
// as `slambooster run --camera-mount`, the daemon's source.camera_mount and a bag's /tf_static give it. One
// rule for every door (issue 53): seven finite numbers, the position within kMaxCameraMountM of the base, the
// quaternion of unit length (within kMountQuaternionTolerance, then normalised). Header-only: the bag plugin
// (a module without the project's static libraries) uses it too.

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "core/error.h"

namespace sb::odometry {

inline constexpr double kMaxCameraMountM = 100.0;           // a camera further from its base is a typo
inline constexpr double kMountQuaternionTolerance = 1e-3;   // |norm - 1| accepted, as odometry.txt and ?ODOM

// Why a rotation given as a quaternion (w, x, y, z) cannot be taken (empty: it can). Zero, non-finite or not
// of unit length: a zero quaternion is not "no rotation".
inline std::string quaternionProblem(double w, double x, double y, double z) {
  const double n = std::sqrt(w * w + x * x + y * y + z * z);
  if (!std::isfinite(n)) return "the quaternion is not finite";
  if (std::abs(n - 1.0) > kMountQuaternionTolerance) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "the quaternion is not of unit length (its norm is %g)", n);
    return buf;
  }
  return "";
}

// Throws sb::Error "<what> '<text>' ..." naming what is wrong.
inline Eigen::Isometry3d parseCameraMount(const std::string& text, const std::string& what) {
  std::istringstream in(text);
  double v[7];
  for (double& x : v)
    if (!(in >> x) || !std::isfinite(x))
      throw Error(what + " '" + text + "' must be seven finite numbers \"x y z qx qy qz qw\" (metres, unit quaternion)");
  std::string rest;
  if (in >> rest) throw Error(what + " '" + text + "' has more than seven numbers \"x y z qx qy qz qw\"");
  for (int i = 0; i < 3; ++i)
    if (std::abs(v[i]) > kMaxCameraMountM)
      throw Error(what + " '" + text + "': the camera must lie within " + std::to_string(int(kMaxCameraMountM)) +
                  " m of the base (x y z in metres)");
  if (const std::string q = quaternionProblem(v[6], v[3], v[4], v[5]); !q.empty())
    throw Error(what + " '" + text + "': " + q);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(v[6], v[3], v[4], v[5]).normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  return T;
}

}  // namespace sb::odometry
