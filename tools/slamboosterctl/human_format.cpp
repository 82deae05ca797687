#include "tools/slamboosterctl/human_format.h"

#include <cstdio>
#include <sstream>
#include <type_traits>

#include "pipeline/knobs.h"

namespace sb::ctl {

namespace {

double num(const nlohmann::json& m, const char* key) {
  auto it = m.find(key);
  return it != m.end() && it->is_number() ? it->get<double>() : 0.0;
}

std::string str(const nlohmann::json& m, const char* key) {
  auto it = m.find(key);
  if (it == m.end()) return "";
  return it->is_string() ? it->get<std::string>() : it->dump();
}

bool flag(const nlohmann::json& m, const char* key) {
  auto it = m.find(key);
  return it != m.end() && it->is_boolean() && it->get<bool>();
}

std::string vec(const nlohmann::json& m, const char* key, int precision) {
  auto it = m.find(key);
  if (it == m.end() || !it->is_array()) return "?";
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(precision);
  for (size_t i = 0; i < it->size(); ++i)
    s << (i ? " " : "") << ((*it)[i].is_number() ? (*it)[i].get<double>() : 0.0);
  return s.str();
}

std::string formatPose(const nlohmann::json& m) {
  // The tracking state (proto_minor 2); an older daemon's POSE has only the tracked flag.
  std::string state = m.contains("state") && m["state"].is_string() ? m["state"].get<std::string>()
                      : flag(m, "tracked")                          ? "tracked"
                                                                    : "lost";
  if (state == "lost") state = "LOST";
  char buf[256];
  std::snprintf(buf, sizeof buf, "POSE   frame %6s  t %.3f s  position %s m  q %s  %s%s  v %.4f m/frame",
                str(m, "frame").c_str(), num(m, "timestamp"), vec(m, "position", 3).c_str(),
                vec(m, "quaternion", 3).c_str(), state.c_str(), flag(m, "corrected") ? " corrected" : "",
                num(m, "velocity"));
  return buf;
}

std::string formatKnobs(const nlohmann::json& m) {
  std::string knobs;  // "csr=1 icp=1e-05 pd=10:5:4 tr=1 ir=2": each knob of pipeline/knobs.h's table
  const sb::Knobs names{};
  sb::forEachKnobField(names, [&](const char* name, const auto& member) {
    std::string value;
    if constexpr (std::is_arithmetic_v<std::decay_t<decltype(member)>>) {
      value = str(m, name);
    } else if (m.contains(name) && m[name].is_array()) {
      for (const auto& v : m[name]) value += (value.empty() ? "" : ":") + v.dump();
    }
    knobs += (knobs.empty() ? "" : " ") + std::string(name) + "=" + value;
  });
  std::string pinned;
  if (m.contains("pinned") && m["pinned"].is_array())
    for (const auto& v : m["pinned"])
      pinned += (pinned.empty() ? "" : ",") + (v.is_string() ? v.get<std::string>() : v.dump());
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "KNOBS  frame %6s  %s  %.1f ms  controller %s%s%s", str(m, "frame").c_str(), knobs.c_str(),
                num(m, "computation_ms"),
                str(m, "controller").c_str(), pinned.empty() ? "" : "  pinned ", pinned.c_str());
  return buf;
}

std::string formatEnergy(const nlohmann::json& m) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "ENERGY frame %6s  %.4f J  %.2f W  meter %s", str(m, "frame").c_str(),
                num(m, "joules"), num(m, "mean_w"), str(m, "meter").c_str());
  return buf;
}

}  // namespace

std::string formatMessage(const nlohmann::json& m) {
  const std::string cls = str(m, "class");
  if (cls == "POSE") return formatPose(m);
  if (cls == "KNOBS") return formatKnobs(m);
  if (cls == "ENERGY") return formatEnergy(m);
  if (cls == "ERROR") return "ERROR  " + str(m, "message");
  if (cls == "VERSION")
    return "slamboosterd " + str(m, "release") + " (protocol " + str(m, "proto_major") + "." +
           str(m, "proto_minor") + ")";
  if (cls == "STATUS") return formatStatus(m);
  return m.dump();
}

std::string formatStatus(const nlohmann::json& m) {
  std::ostringstream s;
  const auto row = [&](const std::string& key, const std::string& value) {
    s << "  " << key << std::string(key.size() < 14 ? 14 - key.size() : 1, ' ') << value << "\n";
  };
  char buf[128];
  s << "slamboosterd " << str(m, "state") << "\n";
  if (m.contains("source") && m["source"].is_object()) {
    const auto& src = m["source"];
    row("source", str(src, "type") + " " + str(src, "path") + " (" + str(src, "state") + ", " +
                      str(src, "frames") + " frames read" + (flag(src, "live") ? ", live" : "") + ")");
  }
  std::snprintf(buf, sizeof buf, "%s processed, %s tracked, %.1f fps, %.1f ms/frame computation",
                str(m, "frames").c_str(), str(m, "tracked").c_str(), num(m, "fps"), num(m, "computation_ms"));
  row("frames", buf);
  if (m.contains("tracking_state") && m["tracking_state"].is_object()) {
    const auto& t = m["tracking_state"];
    row("tracking", str(t, "current") + " (lost " + str(t, "lost_stretches") + " times, " + str(t, "lost_frames") +
                        " frames; relocalised " + str(t, "relocalisations") + " times)");
  }
  row("drops", str(m, "drops"));
  row("controller",
      str(m, "controller") +
          (m.contains("pinned") && !m["pinned"].empty() ? "  pinned " + m["pinned"].dump() : ""));
  row("meter", str(m, "meter"));
  row("slam cpus", str(m, "cpus") + " (" + str(m, "threads") + " compute threads)");
  row("outputs", str(m, "output_dir"));
  row("clients", str(m, "clients"));
  std::snprintf(buf, sizeof buf, "%.0f s", num(m, "uptime_s"));
  row("uptime", buf);
  if (m.contains("error")) row("error", str(m, "error"));
  std::string out = s.str();
  if (!out.empty()) out.pop_back();
  return out;
}

}  // namespace sb::ctl
