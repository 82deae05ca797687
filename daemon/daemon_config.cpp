#include "daemon/daemon_config.h"

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/config_reader.h"
#include "core/error.h"
#include "core/input_file.h"
#include "core/json_text.h"
#include "daemon/cpu_affinity.h"

namespace sb::daemon {

namespace {

// "0660" -> 0660; anything but 1-4 octal digits up to 0777 is refused.
unsigned parseMode(const ConfigReader& r, const std::string& text) {
  const std::string allowed = "an octal permission string like \"0660\" (at most 0777)";
  if (text.empty() || text.size() > 4 || text.find_first_not_of("01234567") != std::string::npos)
    r.fail("mode", allowed);
  const unsigned mode = static_cast<unsigned>(std::stoul(text, nullptr, 8));
  if (mode > 0777) r.fail("mode", allowed);
  return mode;
}

std::string formatMode(unsigned mode) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "%04o", mode);
  return buf;
}

void readSlam(ConfigReader& r, SlamConfig& s) {
  r.string("cpus", s.cpus);
  r.integer("threads", s.threads, 0, 1024);
  r.string("pipeline_config", s.pipelineConfig);
  r.string("controller", s.controller);
  r.string("controller_config", s.controllerConfig);
  try {
    validateCpuSpec(s.cpus);
  } catch (const Error& e) {
    r.fail("cpus", std::string("\"auto\", \"all\" or a CPU list like \"4-7\" (") + e.what() + ")");
  }
  if (s.controller.empty()) r.fail("controller", "a controller name, e.g. \"default\"");
}

constexpr double kMib = 1024.0 * 1024.0;
constexpr double kMinKeepSlabsMib = 16.0;
constexpr double kMinSegmentSeconds = 1.0;  // output.rotation.segment_s, when not 0

void readRotation(ConfigReader& r, RotationConfig& c) {
  r.string("mode", c.mode, {"live", "always", "never"});
  r.number("segment_mib", c.segmentMib, 0.0625, 1048576.0);
  r.number("segment_s", c.segmentSeconds, 0.0, 31.0 * 86400.0);
  if (c.segmentSeconds > 0.0 && c.segmentSeconds < kMinSegmentSeconds)  // 1e-9: two files per frame
    r.fail("segment_s", "0 (no age limit) or at least " + std::to_string(int(kMinSegmentSeconds)) +
                            " s (segments are whole files, not a few frames each)");
  r.number("keep_mib", c.keepMib, 0.5, 1073741824.0);
  r.integer("keep_segments", c.keepSegments, 0, 100000000);
  r.number("min_free_mib", c.minFreeMib, 0.0, 1073741824.0);
  r.number("keep_slabs_mib", c.keepSlabsMib, 0.0, 1073741824.0);
  if (c.keepSlabsMib > 0.0 && c.keepSlabsMib < kMinKeepSlabsMib)
    r.fail("keep_slabs_mib", "0 (no limit) or at least " + std::to_string(int(kMinKeepSlabsMib)) +
                                 " MiB (a few slabs of a 256^3 volume's map)");
  try {
    validateRetention(retentionLimits(c));
  } catch (const Error& e) {
    r.fail("keep_mib",
           "at least 8 x segment_mib (" + std::to_string(8 * c.segmentMib) + " MiB): " + e.what());
  }
}

void readOutput(ConfigReader& r, OutputConfig& o) {
  r.string("dir", o.dir);
  r.boolean("mesh", o.mesh);
  r.boolean("model_png", o.modelPng);
  r.boolean("report", o.report);
  r.string("navmap", o.navmap);
  r.number("navmap_period_s", o.navmapPeriodS, 0.5, 86400.0);
  r.string("map_store", o.mapStore);
  r.number("map_store_keep_mib", o.mapStoreKeepMib, 0.0, 1073741824.0);
  r.section("rotation", [&](ConfigReader& s) { readRotation(s, o.rotation); });
  if (o.dir.empty()) r.fail("dir", "a directory for trajectory.tum, frames.jsonl and summary.json (not empty)");
}

void readPower(ConfigReader& r, PowerRefConfig& p) { r.string("config", p.config); }

void readSocket(ConfigReader& r, SocketConfig& s) {
  r.string("path", s.path);
  std::string mode = formatMode(s.mode);
  r.string("mode", mode);
  s.mode = parseMode(r, mode);
  r.string("control_group", s.controlGroup);
  r.integer("max_clients", s.maxClients, 1, 4096);
  r.integer("max_clients_per_uid", s.maxClientsPerUid, 1, 4096);
  r.integer("max_request_bytes", s.maxRequestBytes, 64, 1 << 20);
  size_t kib = s.clientBufferBytes / 1024;
  r.integer("client_buffer_kib", kib, 4, 65536);
  s.clientBufferBytes = kib * 1024;
  r.number("client_stall_s", s.clientStallSeconds, 0.1, 3600.0);
  // sockaddr_un::sun_path holds 108 bytes including the terminating NUL.
  if (s.path.empty() || s.path.size() > 107)
    r.fail("path", "a socket path of 1 to 107 bytes (the Unix socket limit)");
}

DaemonConfig parseDaemonConfigOrThrow(const nlohmann::json& j, const std::string& where);

}  // namespace

RetentionLimits retentionLimits(const RotationConfig& c) {
  RetentionLimits l;
  l.segmentBytes = static_cast<uint64_t>(c.segmentMib * kMib);
  l.segmentSeconds = c.segmentSeconds;
  l.keepBytes = static_cast<uint64_t>(c.keepMib * kMib);
  l.keepSegments = c.keepSegments;
  l.minFreeBytes = static_cast<uint64_t>(c.minFreeMib * kMib);
  return l;
}

bool rotates(const RotationConfig& c, bool liveSource) {
  return c.mode == "always" || (c.mode == "live" && liveSource);
}

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
  ConfigReader r(j, where);
  r.section("source", [&](ConfigReader& s) { c.source.read(s); });
  r.section("slam", [&](ConfigReader& s) { readSlam(s, c.slam); });
  r.section("output", [&](ConfigReader& s) { readOutput(s, c.output); });
  r.section("socket", [&](ConfigReader& s) { readSocket(s, c.socket); });
  r.section("power", [&](ConfigReader& s) { readPower(s, c.power); });
  r.number("status_interval_s", c.statusIntervalSeconds, 0.05, 3600.0);
  if (c.source.type == "push" && !c.source.path.empty()) {
    // The push source's socket and the control socket must be two files (they would replace each other).
    const auto normal = [](const std::string& p) { return std::filesystem::absolute(p).lexically_normal(); };
    if (normal(c.source.path) == normal(c.socket.path))
      throw ConfigError(where + ": 'source.path' = " + quoteForMessage(c.source.path) +
                        " is the control socket's path (socket.path): the push source needs a socket of its own");
  }
  r.string("log_level", c.logLevel, {"trace", "debug", "info", "warn", "error"});
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


nlohmann::json daemonConfigToJson(const DaemonConfig& c) {
  return {{"source", c.source.toJson()},
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
            {"report", c.output.report},
            {"navmap", c.output.navmap},
            {"navmap_period_s", c.output.navmapPeriodS},
            {"map_store", c.output.mapStore},
            {"map_store_keep_mib", c.output.mapStoreKeepMib},
            {"rotation",
             {{"mode", c.output.rotation.mode},
              {"segment_mib", c.output.rotation.segmentMib},
              {"segment_s", c.output.rotation.segmentSeconds},
              {"keep_mib", c.output.rotation.keepMib},
              {"keep_segments", c.output.rotation.keepSegments},
              {"min_free_mib", c.output.rotation.minFreeMib},
              {"keep_slabs_mib", c.output.rotation.keepSlabsMib}}}}},
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
