#include "ros/daemon_reports.h"

#include <cstdio>
#include <nlohmann/json.hpp>
#include <type_traits>

#include "core/error.h"
#include "core/pose_fields.h"

namespace sb::ros_bridge {

namespace {

const nlohmann::json& member(const nlohmann::json& j, const char* cls, const char* key) {
  const auto it = j.find(key);
  if (it == j.end()) throw Error(std::string(cls) + " report without '" + key + "': is this a slamboosterd socket?");
  return *it;
}

double number(const nlohmann::json& j, const char* cls, const char* key) {
  const auto& v = member(j, cls, key);
  if (!v.is_number()) throw Error(std::string(cls) + " report: '" + key + "' is not a number: " + v.dump());
  return v.get<double>();
}

bool flag(const nlohmann::json& j, const char* cls, const char* key) {
  const auto& v = member(j, cls, key);
  if (!v.is_boolean()) throw Error(std::string(cls) + " report: '" + key + "' is not true/false: " + v.dump());
  return v.get<bool>();
}

template <size_t N>
std::array<double, N> numbers(const nlohmann::json& j, const char* cls, const char* key) {
  const auto& v = member(j, cls, key);
  if (!v.is_array() || v.size() != N)
    throw Error(std::string(cls) + " report: '" + key + "' is not an array of " + std::to_string(N) +
                " numbers: " + v.dump());
  std::array<double, N> out{};
  for (size_t i = 0; i < N; ++i) {
    if (!v[i].is_number())
      throw Error(std::string(cls) + " report: '" + key + "' holds a non-number: " + v.dump());
    out[i] = v[i].get<double>();
  }
  return out;
}

uint64_t frameOf(const nlohmann::json& j, const char* cls) {
  const auto& v = member(j, cls, "frame");
  if (!v.is_number_unsigned()) throw Error(std::string(cls) + " report: 'frame' is not a frame number: " + v.dump());
  return v.get<uint64_t>();
}

}  // namespace

TrackingState trackingStateOf(const PoseReport& pose) {
  if (pose.state) {
    return trackingStateFromName(*pose.state).value_or(TrackingState::lost);
  }
  if (!pose.tracked) return TrackingState::lost;
  if (pose.corrected || pose.constrained == false) return TrackingState::weak;
  return TrackingState::good;
}

PoseReport parsePose(const nlohmann::json& j) {
  constexpr const char* cls = "POSE";
  // Each member by its name in the pose record's table (core/pose_fields.h), the one POSE is written from.
  const auto name = [](auto member) { return poseField(member).name; };
  const auto text = [&](const char* key) -> std::optional<std::string> {
    const auto it = j.find(key);
    return it != j.end() && it->is_string() ? std::optional<std::string>(it->get<std::string>()) : std::nullopt;
  };
  PoseReport p;
  p.frame = frameOf(j, cls);
  p.timestamp = number(j, cls, name(&PoseFields::timestamp));
  p.position = numbers<3>(j, cls, name(&PoseFields::position));
  p.quaternion = numbers<4>(j, cls, name(&PoseFields::quaternion));
  p.tracked = flag(j, cls, name(&PoseFields::tracked));
  if (const char* k = name(&PoseFields::corrected); j.contains(k)) p.corrected = flag(j, cls, k);
  // The velocity under its name since protocol 1.3, else under the older one.
  if (const char* k = name(&PoseFields::velocityMPerFrame); j.contains(k))
    p.velocity = number(j, cls, k);
  else if (j.contains(kPoseLegacyVelocity))
    p.velocity = number(j, cls, kPoseLegacyVelocity);
  if (const char* k = name(&PoseFields::constrained); j.contains(k)) p.constrained = flag(j, cls, k);
  if (const char* k = name(&PoseFields::conditioning); j.contains(k)) p.conditioning = number(j, cls, k);
  p.weakestMotion = text(name(&PoseFields::weakestMotion)).value_or("");
  p.state = text(name(&PoseFields::state));
  if (const char* k = name(&PoseFields::odometry); j.contains(k)) p.odometry = flag(j, cls, k);
  if (const char* k = name(&PoseFields::odometryDriftM); j.contains(k)) p.odometryDriftM = number(j, cls, k);
  p.keptMap = text(name(&PoseFields::keptMap)).value_or("");
  p.trackingState = trackingStateOf(p);
  return p;
}

KnobsReport parseKnobs(const nlohmann::json& j) {
  constexpr const char* cls = "KNOBS";
  KnobsReport k;
  k.frame = frameOf(j, cls);
  if (const auto it = j.find("controller"); it != j.end() && it->is_string()) k.controller = *it;
  forEachKnobField(k.knobs, [&](const char* name, auto& member) {
    if constexpr (std::is_arithmetic_v<std::decay_t<decltype(member)>>) {
      member = static_cast<std::decay_t<decltype(member)>>(number(j, cls, name));
    } else {
      const auto levels = numbers<std::tuple_size_v<std::decay_t<decltype(member)>>>(j, cls, name);
      for (size_t i = 0; i < levels.size(); ++i) member[i] = static_cast<int>(levels[i]);
    }
  });
  if (j.contains("computation_ms")) k.computationMs = number(j, cls, "computation_ms");
  return k;
}

std::vector<std::pair<std::string, std::string>> knobValues(const KnobsReport& k) {
  const auto text = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return std::string(buf);
  };
  std::vector<std::pair<std::string, std::string>> values;
  forEachKnobField(k.knobs, [&](const char* name, const auto& member) {
    if constexpr (std::is_arithmetic_v<std::decay_t<decltype(member)>>) {
      values.emplace_back(name, text(member));
    } else {
      std::string list;
      for (int v : member) list += (list.empty() ? "" : ",") + text(v);
      values.emplace_back(name, list);
    }
  });
  return values;
}

EnergyReport parseEnergy(const nlohmann::json& j) {
  constexpr const char* cls = "ENERGY";
  EnergyReport e;
  e.frame = frameOf(j, cls);
  e.joules = number(j, cls, "joules");
  if (j.contains("mean_w")) e.meanWatts = number(j, cls, "mean_w");
  if (const auto it = j.find("meter"); it != j.end() && it->is_string()) e.meter = *it;
  return e;
}

}  // namespace sb::ros_bridge
