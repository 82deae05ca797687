#include "daemon/daemon_config.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/json_text.h"
#include "daemon/cpu_affinity.h"
#include "daemon/json_reader.h"
#include "daemon/source_registry.h"

namespace sb::daemon {

namespace {

unsigned parseMode(const std::string& where, const std::string& text) {
  const std::string allowed = "an octal permission string like \"0660\" (at most 0777)";
  if (text.empty() || text.size() > 4 || text.find_first_not_of("01234567") != std::string::npos)
    throw Error(where + ": 'mode' = \"" + text + "\" is not allowed; expected " + allowed);
  const unsigned mode = static_cast<unsigned>(std::stoul(text, nullptr, 8));
  if (mode > 0777) throw Error(where + ": 'mode' = \"" + text + "\" is not allowed; expected " + allowed);
  return mode;
}

std::string formatMode(unsigned mode) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "%04o", mode);
  return buf;
}

void readCamera(const nlohmann::json& j, const std::string& where, CameraConfig& c) {
  JsonObjectReader r(j, where + ": source: camera");
  r.string("uri", c.uri);
  r.integer("width", c.width, 1, 8192);
  r.integer("height", c.height, 1, 8192);
  r.integer("fps", c.fps, 1, 1000);
  r.number("fx", c.fx, 0.0, 1e5);
  r.number("fy", c.fy, 0.0, 1e5);
  r.number("cx", c.cx, 0.0, 1e5);
  r.number("cy", c.cy, 0.0, 1e5);
  r.number("frame_timeout_s", c.frameTimeoutSeconds, 0.05, 3600.0);
  r.number("reconnect_min_s", c.reconnectMinSeconds, 0.01, 3600.0);
  r.number("reconnect_max_s", c.reconnectMaxSeconds, 0.01, 3600.0);
  r.finish();
  if (c.reconnectMaxSeconds < c.reconnectMinSeconds)
    throw Error(r.where() + ": 'reconnect_max_s' must be >= 'reconnect_min_s'");
}

void readSource(const nlohmann::json& j, const std::string& where, SourceConfig& s) {
  JsonObjectReader r(j, where + ": source");
  r.string("type", s.type);
  r.string("path", s.path);
  r.choice("pacing", s.pacing, {"recorded", "fast"});
  r.number("speed", s.speed, 0.01, 100.0);
  r.choice("at_end", s.atEnd, {"stop", "loop", "exit"});
  r.integer("max_frames", s.maxFrames, 0, 100000000);
  r.number("depth_scale", s.depthScale, 0.0, 1e6);
  r.integer("queue_frames", s.queueFrames, 1, 256);
  if (const auto* c = r.object("camera")) readCamera(*c, where, s.camera);
  r.finish();
  const auto types = sourceTypes();
  if (std::find(types.begin(), types.end(), s.type) == types.end()) {
    std::string known;
    for (const auto& t : types) known += (known.empty() ? "\"" : ", \"") + t + "\"";
    throw Error(r.where() + ": 'type' = \"" + s.type + "\" is not allowed; expected one of " + known);
  }
}

void readSlam(const nlohmann::json& j, const std::string& where, SlamConfig& s) {
  JsonObjectReader r(j, where + ": slam");
  r.string("cpus", s.cpus);
  r.integer("threads", s.threads, 0, 1024);
  r.string("pipeline_config", s.pipelineConfig);
  r.string("controller", s.controller);
  r.string("controller_config", s.controllerConfig);
  r.finish();
  try {
    validateCpuSpec(s.cpus);
  } catch (const Error& e) {
    throw Error(r.where() + ": 'cpus': " + e.what());
  }
  if (s.controller.empty())
    throw Error(where + ": slam: 'controller' must name a controller, e.g. \"default\"");
}

void readOutput(const nlohmann::json& j, const std::string& where, OutputConfig& o) {
  JsonObjectReader r(j, where + ": output");
  r.string("dir", o.dir);
  r.boolean("mesh", o.mesh);
  r.boolean("model_png", o.modelPng);
  r.boolean("report", o.report);
  r.finish();
  if (o.dir.empty())
    throw Error(where + ": output: 'dir' must not be empty (where trajectory.tum is written)");
}

void readPower(const nlohmann::json& j, const std::string& where, PowerRefConfig& p) {
  JsonObjectReader r(j, where + ": power");
  r.string("config", p.config);
  r.finish();
}

void readSocket(const nlohmann::json& j, const std::string& where, SocketConfig& s) {
  JsonObjectReader r(j, where + ": socket");
  r.string("path", s.path);
  std::string mode = formatMode(s.mode);
  r.string("mode", mode);
  s.mode = parseMode(r.where(), mode);
  r.string("control_group", s.controlGroup);
  r.integer("max_clients", s.maxClients, 1, 4096);
  r.integer("max_clients_per_uid", s.maxClientsPerUid, 1, 4096);
  r.integer("max_request_bytes", s.maxRequestBytes, 64, 1 << 20);
  size_t kib = s.clientBufferBytes / 1024;
  r.integer("client_buffer_kib", kib, 4, 65536);
  s.clientBufferBytes = kib * 1024;
  r.number("client_stall_s", s.clientStallSeconds, 0.1, 3600.0);
  r.finish();
  if (s.path.empty()) throw Error(where + ": socket: 'path' must not be empty");
  // sockaddr_un::sun_path holds 108 bytes including the terminating NUL.
  if (s.path.size() > 107)
    throw Error(where + ": socket: 'path' = \"" + s.path +
                "\" is longer than 107 bytes (the Unix socket limit)");
}

DaemonConfig parseDaemonConfigOrThrow(const nlohmann::json& j, const std::string& where);

}  // namespace

DaemonConfig parseDaemonConfig(const nlohmann::json& j, const std::string& where) {
  try {
    return parseDaemonConfigOrThrow(j, where);
  } catch (const ConfigError&) {
    throw;
  } catch (const Error& e) {
    throw ConfigError(e.what());
  }
}

namespace {

DaemonConfig parseDaemonConfigOrThrow(const nlohmann::json& j, const std::string& where) {
  DaemonConfig c;
  JsonObjectReader r(j, where);
  if (const auto* s = r.object("source")) readSource(*s, where, c.source);
  if (const auto* s = r.object("slam")) readSlam(*s, where, c.slam);
  if (const auto* s = r.object("output")) readOutput(*s, where, c.output);
  if (const auto* s = r.object("socket")) readSocket(*s, where, c.socket);
  if (const auto* s = r.object("power")) readPower(*s, where, c.power);
  r.number("status_interval_s", c.statusIntervalSeconds, 0.05, 3600.0);
  r.choice("log_level", c.logLevel, {"trace", "debug", "info", "warn", "error"});
  r.finish();
  return c;
}

}  // namespace

void applyOverride(nlohmann::json& j, const std::string& assignment) {
  const auto eq = assignment.find('=');
  const std::string usage = "'" + assignment + "': an override is section.key=value, e.g. source.pacing=fast";
  if (eq == std::string::npos || eq == 0) throw ConfigError(usage);
  const std::string path = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  std::string ignored;
  nlohmann::json value =
      tryParseJson(text, ignored).value_or(nlohmann::json(text));  // a plain string needs no quotes
  nlohmann::json* node = &j;
  std::string at = "the configuration";
  size_t start = 0;
  while (true) {
    const auto dot = path.find('.', start);
    const std::string key = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (key.empty()) throw ConfigError(usage);
    // Never replace what the file says with an object: a config that is not an object stays an error.
    if (!node->is_object())
      throw ConfigError("'" + assignment + "': cannot set '" + key + "' because " + at + " is " +
                        describeJson(*node) + ", not a JSON object; fix the config file");
    if (dot == std::string::npos) {
      (*node)[key] = value;
      return;
    }
    if (!node->contains(key)) (*node)[key] = nlohmann::json::object();
    node = &(*node)[key];
    at = "'" + path.substr(0, dot) + "'";
    start = dot + 1;
  }
}

nlohmann::json readJsonFile(const std::string& path) {
  try {
    return sb::readJsonFile(path, "config file");
  } catch (const ConfigError&) {
    throw;
  } catch (const Error& e) {
    throw ConfigError(e.what());
  }
}

nlohmann::json daemonConfigToJson(const DaemonConfig& c) {
  return {{"source",
           {{"type", c.source.type},
            {"path", c.source.path},
            {"pacing", c.source.pacing},
            {"speed", c.source.speed},
            {"at_end", c.source.atEnd},
            {"max_frames", c.source.maxFrames},
            {"depth_scale", c.source.depthScale},
            {"queue_frames", c.source.queueFrames},
            {"camera",
             {{"uri", c.source.camera.uri},
              {"width", c.source.camera.width},
              {"height", c.source.camera.height},
              {"fps", c.source.camera.fps},
              {"fx", c.source.camera.fx},
              {"fy", c.source.camera.fy},
              {"cx", c.source.camera.cx},
              {"cy", c.source.camera.cy},
              {"frame_timeout_s", c.source.camera.frameTimeoutSeconds},
              {"reconnect_min_s", c.source.camera.reconnectMinSeconds},
              {"reconnect_max_s", c.source.camera.reconnectMaxSeconds}}}}},
          {"slam",
           {{"cpus", c.slam.cpus},
            {"threads", c.slam.threads},
            {"pipeline_config", c.slam.pipelineConfig},
            {"controller", c.slam.controller},
            {"controller_config", c.slam.controllerConfig}}},
          {"output",
           {{"dir", c.output.dir},
            {"mesh", c.output.mesh},
            {"model_png", c.output.modelPng},
            {"report", c.output.report}}},
          {"socket",
           {{"path", c.socket.path},
            {"mode", formatMode(c.socket.mode)},
            {"control_group", c.socket.controlGroup},
            {"max_clients", c.socket.maxClients},
            {"max_clients_per_uid", c.socket.maxClientsPerUid},
            {"max_request_bytes", c.socket.maxRequestBytes},
            {"client_buffer_kib", c.socket.clientBufferBytes / 1024},
            {"client_stall_s", c.socket.clientStallSeconds}}},
          {"power", {{"config", c.power.config}}},
          {"status_interval_s", c.statusIntervalSeconds},
          {"log_level", c.logLevel}};
}

}  // namespace sb::daemon
