#pragma once
// The ?ODOM request (protocol 1.5; docs/protocol.md): any local client pushes the robot's odometry, stamped
// camera poses in its odometry frame (odometry/odometry_track.h: T_camera_to_odom, optical frame, seconds on
// the depth frames' clock), which the daemon adds to the live track the SLAM thread reads. One sample
//   ?ODOM={"t":12.34,"position":[x,y,z],"quaternion":[qx,qy,qz,qw],"covariance":[36 numbers]}
// or a batch ?ODOM={"samples":[{...},...]} of at most kMaxOdomSamples, stamps increasing. The covariance is
// optional: row-major 6x6 of (x y z rx ry rz), m^2 and rad^2, as nav_msgs/Odometry's pose.covariance.
// Pure parsing, no I/O; never throws.

#include <array>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace sb::daemon {

inline constexpr size_t kMaxOdomSamples = 64;        // samples in one ?ODOM batch
inline constexpr double kOdomQuaternionTolerance = 1e-3;  // |norm - 1| accepted (then normalised)

struct OdomSample {
  double t = 0.0;                        // seconds, the depth frames' clock
  std::array<double, 3> position{};      // metres, in the odometry frame
  std::array<double, 4> quaternion{};    // qx qy qz qw, unit
  std::optional<std::array<double, 36>> covariance;
};

struct OdomRequest {
  std::vector<OdomSample> samples;  // stamps strictly increasing
};

// Reads ?ODOM's argument object. False with `error` naming the field (e.g. samples[3].quaternion) when
// something is missing, not a finite number, of the wrong length, not a unit quaternion, or stamps do not
// increase.
bool readOdom(const nlohmann::json& args, OdomRequest& out, std::string& error);

}  // namespace sb::daemon
