#include "daemon/odom_request.h"

#include <cmath>

#include "drivers/stamp_gate.h"

namespace sb::daemon {

namespace {

constexpr double kMaxOdomPositionM = 1e6;  // 1000 km: beyond it a pushed position is a unit error, not a drive

// Reads `n` finite numbers of the array `key` of `sample`.
template <size_t N>
bool numbers(const nlohmann::json& sample, const char* key, const std::string& where, std::array<double, N>& out,
             std::string& error) {
  const auto it = sample.find(key);
  if (it == sample.end() || !it->is_array() || it->size() != N) {
    error = "?ODOM: '" + where + key + "' must be an array of " + std::to_string(N) + " numbers";
    return false;
  }
  for (size_t i = 0; i < N; ++i) {
    const nlohmann::json& v = (*it)[i];
    if (!v.is_number() || !std::isfinite(v.get<double>())) {
      error = "?ODOM: '" + where + key + "[" + std::to_string(i) + "]' must be a finite number";
      return false;
    }
    out[i] = v.get<double>();
  }
  return true;
}

bool readSample(const nlohmann::json& j, const std::string& where, OdomSample& s, std::string& error) {
  if (!j.is_object()) {
    error = "?ODOM: '" + (where.empty() ? std::string("the argument") : where.substr(0, where.size() - 1)) +
            "' must be an object {\"t\":..,\"position\":[..],\"quaternion\":[..]}";
    return false;
  }
  const auto t = j.find("t");
  // The stamps every input door accepts (drivers/stamp_gate.h): one absurd stamp would otherwise stand as the
  // newest and refuse every later sample (stamps must increase) for the rest of the run.
  if (t == j.end() || !t->is_number() || !(t->get<double>() >= 0.0 && t->get<double>() <= kMaxStampSeconds)) {
    error = "?ODOM: '" + where + "t' must be a number of seconds on the depth frames' clock, in [0, 1e10]";
    return false;
  }
  s.t = t->get<double>();
  if (!numbers(j, "position", where, s.position, error)) return false;
  for (const double x : s.position)
    if (!(std::abs(x) <= kMaxOdomPositionM)) {
      error = "?ODOM: '" + where + "position' must lie within " + std::to_string(int(kMaxOdomPositionM)) +
              " m of the odometry frame's origin";
      return false;
    }
  if (!numbers(j, "quaternion", where, s.quaternion, error)) return false;
  const auto& q = s.quaternion;
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!(std::abs(norm - 1.0) <= kOdomQuaternionTolerance)) {
    error = "?ODOM: '" + where + "quaternion' must be a unit quaternion [qx,qy,qz,qw] (its norm is " +
            std::to_string(norm) + ")";
    return false;
  }
  if (j.contains("covariance") && !j["covariance"].is_null()) {
    if (!numbers(j, "covariance", where, s.covariance.emplace(), error)) return false;
  }
  return true;
}

}  // namespace

bool readOdom(const nlohmann::json& args, OdomRequest& out, std::string& error) {
  out.samples.clear();
  if (const auto batch = args.find("samples"); batch != args.end()) {
    if (!batch->is_array() || batch->empty() || batch->size() > kMaxOdomSamples) {
      error = "?ODOM: 'samples' must be an array of 1 to " + std::to_string(kMaxOdomSamples) + " samples";
      return false;
    }
    for (size_t i = 0; i < batch->size(); ++i) {
      OdomSample s;
      if (!readSample((*batch)[i], "samples[" + std::to_string(i) + "].", s, error)) return false;
      out.samples.push_back(s);
    }
  } else {
    OdomSample s;
    if (!readSample(args, "", s, error)) return false;
    out.samples.push_back(s);
  }
  for (size_t i = 1; i < out.samples.size(); ++i)
    if (!(out.samples[i].t > out.samples[i - 1].t)) {
      error = "?ODOM: 'samples[" + std::to_string(i) + "].t' must be after the sample before it (stamps increase)";
      return false;
    }
  return true;
}

}  // namespace sb::daemon
