#include "daemon/odom_intake.h"

#include "core/error.h"

namespace sb::daemon {

odometry::OdometrySample toOdometrySample(const OdomSample& s) {
  odometry::OdometrySample out;
  out.timestamp = s.t;
  const auto& q = s.quaternion;
  out.T_camera_to_odom.linear() = Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized().toRotationMatrix();
  out.T_camera_to_odom.translation() = Eigen::Vector3d(s.position[0], s.position[1], s.position[2]);
  if (s.covariance)
    out.covariance = odometry::Matrix6(Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(s.covariance->data()));
  return out;
}

nlohmann::json addOdomSamples(odometry::OdometryTrack& track, const OdomRequest& request) {
  size_t accepted = 0;
  for (const OdomSample& s : request.samples) {
    std::string why;
    if (!track.add(toOdometrySample(s), &why))
      throw Error("?ODOM: '" + (request.samples.size() > 1 ? "samples[" + std::to_string(accepted) + "].t" : "t") + "': " +
                  why + (accepted ? " (the " + std::to_string(accepted) + " samples before it were added)" : ""));
    ++accepted;
  }
  nlohmann::json reply = {{"accepted", accepted}, {"samples", track.size()}};
  if (const auto newest = track.newestStamp()) reply["newest"] = *newest;
  return reply;
}

}  // namespace sb::daemon
