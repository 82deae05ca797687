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
  const uint64_t before = track.added();
  size_t refused = 0;
  std::string firstRefused;
  for (size_t i = 0; i < request.samples.size(); ++i) {
    std::string why;
    if (track.add(toOdometrySample(request.samples[i]), &why)) continue;
    if (refused++ == 0)
      firstRefused = "?ODOM: '" + (request.samples.size() > 1 ? "samples[" + std::to_string(i) + "].t" : "t") + "': " + why;
  }
  // Held samples a later one confirmed count as accepted with it (and not as refused).
  const uint64_t accepted = track.added() - before;
  refused = accepted >= request.samples.size() ? 0 : request.samples.size() - accepted;
  if (accepted == 0 && refused > 0)
    throw Error(firstRefused + (refused > 1 ? " (and the " + std::to_string(refused - 1) + " samples after it)" : ""));
  nlohmann::json reply = {{"accepted", accepted}, {"samples", track.size()},
                          {"capacity", track.params().capacity}};
  if (const auto newest = track.newestStamp()) reply["newest"] = *newest;
  if (const auto oldest = track.oldestStamp()) reply["oldest"] = *oldest;
  if (refused > 0) {
    reply["refused"] = refused;
    reply["refused_first"] = firstRefused;
  }
  return reply;
}

}  // namespace sb::daemon
