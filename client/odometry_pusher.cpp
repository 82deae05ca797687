#include "client/odometry_pusher.h"

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "core/error.h"

namespace sb::client {

namespace {

constexpr size_t kMaxBatch = 64;  // daemon/odom_request.h kMaxOdomSamples

nlohmann::json sampleJson(const odometry::OdometrySample& s) {
  const Eigen::Vector3d p = s.T_camera_to_odom.translation();
  const Eigen::Quaterniond q(s.T_camera_to_odom.rotation());
  nlohmann::json j = {{"t", s.timestamp}, {"position", {p.x(), p.y(), p.z()}}, {"quaternion", {q.x(), q.y(), q.z(), q.w()}}};
  if (s.covariance) {
    nlohmann::json c = nlohmann::json::array();
    for (int r = 0; r < 6; ++r)
      for (int k = 0; k < 6; ++k) c.push_back((*s.covariance)(r, k));  // row-major, as nav_msgs
    j["covariance"] = std::move(c);
  }
  return j;
}

std::string line(const nlohmann::json& batch) {
  return batch.size() == 1 ? "?ODOM=" + batch[0].dump() : "?ODOM=" + nlohmann::json{{"samples", batch}}.dump();
}

}  // namespace

std::vector<std::string> odomRequestLines(const std::vector<odometry::OdometrySample>& samples,
                                          size_t maxLineBytes) {
  std::vector<std::string> lines;
  nlohmann::json batch = nlohmann::json::array();
  size_t bytes = 0;
  for (const odometry::OdometrySample& s : samples) {
    nlohmann::json j = sampleJson(s);
    const size_t size = j.dump().size() + 1;
    if (!batch.empty() && (batch.size() == kMaxBatch || bytes + size + 20 > maxLineBytes)) {
      lines.push_back(line(batch));
      batch = nlohmann::json::array();
      bytes = 0;
    }
    batch.push_back(std::move(j));
    bytes += size;
  }
  if (!batch.empty()) lines.push_back(line(batch));
  return lines;
}

OdomPushResult pushOdometry(Connection& connection, const std::vector<odometry::OdometrySample>& samples,
                            double timeoutSeconds, size_t maxLineBytes) {
  OdomPushResult r;
  for (const std::string& request : odomRequestLines(samples, maxLineBytes)) {
    connection.send(request);
    const nlohmann::json reply = connection.reply("ODOM", timeoutSeconds);
    if (reply.value("class", "") == "ERROR")
      throw Error("slamboosterd refused odometry after " + std::to_string(r.accepted) +
                  " samples: " + reply.value("message", ""));
    r.accepted += reply.value("accepted", size_t{0});
    if (const size_t refused = reply.value("refused", size_t{0})) {
      if (r.refused == 0) r.firstRefused = reply.value("refused_first", "");
      r.refused += refused;
    }
    r.held = reply.value("samples", size_t{0});
    r.capacity = reply.value("capacity", size_t{0});
    r.oldest = reply.contains("oldest") ? std::optional<double>(reply["oldest"].get<double>()) : std::nullopt;
    r.newest = reply.contains("newest") ? std::optional<double>(reply["newest"].get<double>()) : std::nullopt;
  }
  return r;
}

}  // namespace sb::client
