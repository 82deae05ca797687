#include "ros/daemon_reports.h"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <type_traits>

#include "core/error.h"

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

uint64_t frameOf(const nlohmann::json& j, const char* cls, const char* key = "frame") {
  const auto& v = member(j, cls, key);
  if (!v.is_number_unsigned())
    throw Error(std::string(cls) + " report: '" + key + "' is not a frame number: " + v.dump());
  return v.get<uint64_t>();
}

// The string at `key`, when there is one (a member of another type is ignored, as a missing one).
std::optional<std::string> text(const nlohmann::json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_string() ? std::optional<std::string>(it->get<std::string>()) : std::nullopt;
}

// Reads `member` from the message's member `key` by the member's type; a string of another type is ignored.
template <typename T>
void read(const nlohmann::json& j, const char* cls, const char* key, T& member) {
  if constexpr (std::is_same_v<T, uint64_t>) {
    member = frameOf(j, cls, key);
  } else if constexpr (std::is_same_v<T, bool>) {
    member = flag(j, cls, key);
  } else if constexpr (std::is_same_v<T, double> || std::is_same_v<T, std::optional<double>>) {
    member = number(j, cls, key);
  } else if constexpr (std::is_same_v<T, std::string>) {
    if (auto s = text(j, key)) member = std::move(*s);
  } else {  // std::array<double, N>
    member = numbers<std::tuple_size_v<T>>(j, cls, key);
  }
}

}  // namespace

PoseReport parsePose(const nlohmann::json& j) {
  constexpr const char* cls = "POSE";
  PoseReport p;
  // Each member under its POSE name in the pose record's table (core/pose_fields.h), the one POSE is written
  // from; a member read under an earlier row (the velocity under its 1.3 name) keeps that value.
  const std::set<const void*> required = {&p.frame, &p.timestamp, &p.position, &p.quaternion, &p.tracked};
  std::set<const void*> done;
  std::optional<std::string> state;  // the daemon's own state string when it sends one
  forEachPoseField(p, [&](const PoseField& row, auto& member) {
    using T = std::decay_t<decltype(member)>;
    if (!j.contains(row.name) && !required.count(&member)) return;
    if (!done.insert(&member).second) return;
    if constexpr (std::is_same_v<T, TrackingState>)
      state = text(j, row.name);
    else
      read(j, cls, row.name, member);
  });
  if (state)
    p.state = trackingStateFromName(*state).value_or(TrackingState::lost);
  else
    p.state = !p.tracked ? TrackingState::lost
              : p.corrected || !p.constrained ? TrackingState::weak
                                              : TrackingState::good;
  return p;
}

KnobsReport parseKnobs(const nlohmann::json& j) {
  constexpr const char* cls = "KNOBS";
  KnobsReport k;
  // Each member under its KNOBS name in the knob record's table (pipeline/knob_fields.h), the one KNOBS is
  // written from: the frame and every knob are required, the others keep their defaults when absent.
  forEachKnobRecordField(k, [&](const KnobRecordField& row, auto& member) {
    using T = std::decay_t<decltype(member)>;
    if constexpr (std::is_same_v<T, Knobs>) {
      forEachKnobField(member, [&](const char* name, auto& knob) {  // pipeline/knobs.h's table
        if constexpr (std::is_arithmetic_v<std::decay_t<decltype(knob)>>) {
          knob = static_cast<std::decay_t<decltype(knob)>>(number(j, cls, name));
        } else {
          const auto levels = numbers<std::tuple_size_v<std::decay_t<decltype(knob)>>>(j, cls, name);
          for (size_t i = 0; i < levels.size(); ++i) knob[i] = static_cast<int>(levels[i]);
        }
      });
    } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
      const auto it = j.find(row.name);
      if (it == j.end()) return;
      const auto isName = [](const nlohmann::json& n) { return n.is_string(); };
      if (!it->is_array() || !std::all_of(it->begin(), it->end(), isName))
        throw Error(std::string(cls) + " report: '" + row.name + "' is not a list of knob names: " + it->dump());
      member = it->template get<std::vector<std::string>>();
    } else if (j.contains(row.name) || std::is_same_v<T, uint64_t>) {
      read(j, cls, row.name, member);
    }
  });
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
