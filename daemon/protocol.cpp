#include "daemon/protocol.h"

#include <algorithm>
#include <cmath>

#include "core/json_text.h"

namespace sb::daemon {

namespace {

struct CommandName {
  const char* name;
  Command command;
  bool takesObject;  // ?NAME={...} allowed
  bool needsObject;  // ?NAME; not allowed
};

constexpr CommandName kCommands[] = {
    {"WATCH", Command::watch, true, false},      {"POLL", Command::poll, false, false},
    {"STATUS", Command::status, false, false},   {"CONTROL", Command::control, true, true},
    {"VERSION", Command::version, false, false}, {"ODOM", Command::odom, true, true},
    {"MAP", Command::map, false, false},         {"CLOUD", Command::cloud, false, false},
};

std::string knownCommands() {
  std::string s;
  for (const auto& c : kCommands) s += (s.empty() ? "?" : ", ?") + std::string(c.name);
  return s;
}

bool readWatch(const nlohmann::json& args, WatchRequest& w, std::string& error) {
  for (auto it = args.begin(); it != args.end(); ++it) {
    std::optional<bool>* field = nullptr;
    if (it.key() == "enable")
      field = &w.enable;
    else if (it.key() == "pose")
      field = &w.pose;
    else if (it.key() == "knobs")
      field = &w.knobs;
    else if (it.key() == "energy")
      field = &w.energy;
    else
      continue;  // unknown fields are ignored, as clients ignore unknown fields in reports
    if (!it.value().is_boolean()) {
      error = "?WATCH: '" + it.key() + "' must be true or false";  // a known key: short
      return false;
    }
    *field = it.value().get<bool>();
  }
  return true;
}

bool readControl(const nlohmann::json& args, ControlRequest& c, std::string& error) {
  const auto& knobs = pinnableKnobs();
  const auto isKnob = [&](const std::string& k) {
    return std::find(knobs.begin(), knobs.end(), k) != knobs.end();
  };
  std::string list;
  for (const auto& k : knobs) list += (list.empty() ? "" : ", ") + k;
  for (auto it = args.begin(); it != args.end(); ++it) {
    const auto& v = it.value();
    if (it.key() == "controller") {
      if (!v.is_string() || v.get<std::string>().empty() || v.get<std::string>().size() > kMaxNameBytes) {
        error = "?CONTROL: 'controller' must be a controller name (a string of 1 to " +
                std::to_string(kMaxNameBytes) + " bytes)";
        return false;
      }
      c.controller = v.get<std::string>();
    } else if (it.key() == "pin") {
      if (!v.is_object() || v.empty()) {
        error = "?CONTROL: 'pin' must be an object of knob values, e.g. {\"csr\":2}";
        return false;
      }
      for (auto k = v.begin(); k != v.end(); ++k) {
        if (!isKnob(k.key())) {
          error = "?CONTROL: cannot pin unknown knob '" + k.key().substr(0, 60) + "' (knobs: " + list + ")";
          return false;
        }
        if (!k.value().is_number() || !std::isfinite(k.value().get<double>())) {
          error = "?CONTROL: pinned knob '" + k.key() + "' must be a number";
          return false;
        }
        c.pin[k.key()] = k.value().get<double>();
      }
    } else if (it.key() == "unpin") {
      if (v.is_string() && v.get<std::string>() == "all") {
        c.unpin = {"all"};
        continue;
      }
      if (!v.is_array()) {
        error = "?CONTROL: 'unpin' must be \"all\" or an array of knob names";
        return false;
      }
      for (const auto& k : v) {
        if (!k.is_string() || !isKnob(k.get<std::string>())) {
          error = "?CONTROL: cannot unpin " + describeJson(k) + " (knobs: " + list + ")";
          return false;
        }
        c.unpin.push_back(k.get<std::string>());
      }
    }
  }
  if (!c.controller && c.pin.empty() && c.unpin.empty()) {
    error = "?CONTROL: nothing to do; give 'controller', 'pin' or 'unpin'";
    return false;
  }
  return true;
}

}  // namespace

ParseResult parseRequest(std::string_view line) {
  ParseResult result;
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  if (line.empty() || line.front() != '?') {
    result.error = "requests start with '?', e.g. ?WATCH={\"enable\":true}; known: " + knownCommands();
    return result;
  }
  size_t end = 1;
  while (end < line.size() && line[end] >= 'A' && line[end] <= 'Z') ++end;
  const std::string_view name = line.substr(1, end - 1);
  const CommandName* command = nullptr;
  for (const auto& c : kCommands)
    if (name == c.name) command = &c;
  if (!command) {
    result.error = "unknown request '?" + std::string(name.substr(0, 32)) + "'; known: " + knownCommands();
    return result;
  }
  std::string_view rest = line.substr(end);
  nlohmann::json args = nlohmann::json::object();
  if (rest == ";" || rest.empty()) {
    if (command->needsObject) {
      result.error =
          "?" + std::string(command->name) + " needs an argument object: ?" + command->name + "={...}";
      return result;
    }
  } else if (rest.front() == '=' && command->takesObject) {
    rest.remove_prefix(1);
    if (!rest.empty() && rest.back() == ';') rest.remove_suffix(1);
    std::string error;
    auto parsed = tryParseJson(rest, error, kMaxRequestDepth);
    if (!parsed || !parsed->is_object()) {
      result.error = "?" + std::string(command->name) + ": the argument must be one JSON object" +
                     (parsed ? "" : " (argument: " + error + ")");
      return result;
    }
    args = std::move(*parsed);
  } else {
    result.error =
        "?" + std::string(command->name) +
        (command->takesObject ? " must be followed by ';' or '={...}'" : " must be followed by ';'");
    return result;
  }

  Request r;
  r.command = command->command;
  if (r.command == Command::watch && !readWatch(args, r.watch, result.error)) return result;
  if (r.command == Command::control && !readControl(args, r.control, result.error)) return result;
  if (r.command == Command::odom && !readOdom(args, r.odom, result.error)) return result;
  result.request = std::move(r);
  return result;
}

nlohmann::json versionMessage(const std::string& release) {
  return {
      {"class", "VERSION"}, {"release", release}, {"proto_major", kProtoMajor}, {"proto_minor", kProtoMinor}};
}

nlohmann::json poseMessage(const FrameReport& r) {
  nlohmann::json j = {{"class", "POSE"}};
  forEachPoseValue(r.pose, [&](const PoseField& row, nlohmann::json value) { j[row.name] = std::move(value); });
  return j;
}

nlohmann::json knobsMessage(const FrameReport& r) {
  nlohmann::json j = {{"class", "KNOBS"}};
  forEachKnobRecordValue(r.knobs, [&](const KnobRecordField& row, nlohmann::json value) {
    if (row.name)
      j[row.name] = std::move(value);
    else
      j.update(value);  // the knob set: each knob a member, under its name in pipeline/knobs.h's key table
  });
  return j;
}

nlohmann::json energyMessage(const EnergyReport& e) {
  return {{"class", "ENERGY"},
          {"frame", e.frame},
          {"joules", e.joules},
          {"mean_w", e.meanWatts},
          {"meter", e.meter}};
}

nlohmann::json watchMessage(bool enable, bool pose, bool knobs, bool energy) {
  return {{"class", "WATCH"}, {"enable", enable}, {"pose", pose}, {"knobs", knobs}, {"energy", energy}};
}

nlohmann::json statusMessage(nlohmann::json status) {
  status["class"] = "STATUS";
  return status;
}

nlohmann::json errorMessage(const std::string& message) {
  return {{"class", "ERROR"}, {"message", message}};
}

std::string toLine(const nlohmann::json& message) {
  return message.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

nlohmann::json mapMessage(const MapReport& m) {
  nlohmann::json runs = nlohmann::json::array();
  for (size_t i = 0; i < m.cells.size();) {
    size_t j = i;
    while (j < m.cells.size() && m.cells[j] == m.cells[i]) ++j;
    runs.push_back(int(m.cells[i]));
    runs.push_back(j - i);
    i = j;
  }
  nlohmann::json j = {{"class", "MAP"},           {"pass", m.pass},          {"frame", m.frame},
                      {"width", m.width},         {"height", m.height},      {"resolution", m.resolutionM},
                      {"origin", {m.originX, m.originY, 0.0}}, {"up", m.up}, {"runs", std::move(runs)},
                      {"frame_in_world", {{"position", m.framePosition}, {"quaternion", m.frameQuaternion}}}};
  if (!m.octomap.empty()) j["octomap"] = m.octomap;
  return j;
}

void boundCloud(MapReport& m, size_t maxCells) {
  std::sort(m.cloud.begin(), m.cloud.end());
  while (m.cloud.size() > std::max<size_t>(maxCells, 8)) {  // cells either side of 0 never merge
    for (auto& c : m.cloud)
      for (int32_t& v : c) v >>= 1;  // arithmetic shift: floor(v / 2), negative cells included
    std::sort(m.cloud.begin(), m.cloud.end());  // halving keeps no lexicographic order
    m.cloud.erase(std::unique(m.cloud.begin(), m.cloud.end()), m.cloud.end());
    m.cloudResolutionM *= 2.0;
  }
}

nlohmann::json cloudMessage(const MapReport& m) {
  nlohmann::json cells = nlohmann::json::array();
  for (const auto& c : m.cloud)
    for (int32_t v : c) cells.push_back(v);
  return {{"class", "CLOUD"}, {"pass", m.pass}, {"frame", m.frame}, {"resolution", m.cloudResolutionM},
          {"cells", std::move(cells)}};
}

}  // namespace sb::daemon
