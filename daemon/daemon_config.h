#pragma once
// The daemon's configuration: one typed struct, parsed and validated once (config/slamboosterd.json is the
// documented default; config/README.md has the key table). Units are in the names or comments.

#include <cstddef>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/segment_store.h"
#include "daemon/source_config.h"

namespace sb::daemon {

// A configuration problem (bad key, type, value, or a config file that cannot be read): slamboosterd exits 2.
class ConfigError : public Error {
 public:
  using Error::Error;
};

struct SlamConfig {
  std::string cpus = "auto";           // "auto" (big cores from sysfs), "all", or a list like "4-7" or "0,2"
  unsigned threads = 0;                // compute threads; 0 = one per CPU the SLAM thread is pinned to
  std::string pipelineConfig;          // pipeline JSON (config/pipeline.json keys); empty = built-in defaults
  std::string controller = "adaptive";  // controller name (see `slambooster run --help` for the list)
  std::string controllerConfig;        // controller settings JSON, re-read on SIGHUP; empty = defaults
};

// output.rotation: rotation and retention of the per-frame outputs (trajectory, frames.jsonl, energy.jsonl,
// power.csv; core/rotating_file.h) for weeks of live capture. The defaults suit a 16 GB eMMC: at 30 fps the
// outputs take about 40 KB/s (3.4 GB a day), so 4 GiB keeps the last day or so.
struct RotationConfig {
  std::string mode = "live";       // "live": rotate when the source is live (a camera); "always"; "never"
  double segmentMib = 64.0;        // a stream starts a new segment past this size (MiB)
  double segmentSeconds = 3600.0;  // ... or this age (s); 0 = by size only
  double keepMib = 4096.0;    // all segments under output.dir together at most this (MiB); oldest go first
  size_t keepSegments = 0;    // closed segments kept at most (0 = no count limit)
  double minFreeMib = 512.0;  // oldest segments go while the file system has less free space (MiB)
  // The moving volume's map (output.mesh): the slab files of a pass's map_slabs/ together at most this (MiB);
  // the oldest slabs go first. 0 = no limit. Applies whatever `mode` is.
  double keepSlabsMib = 1024.0;
};

// The store's limits in bytes for `rotation`.
RetentionLimits retentionLimits(const RotationConfig& rotation);
// Whether the outputs rotate with `rotation` and a source that is (or is not) live.
bool rotates(const RotationConfig& rotation, bool liveSource);

struct OutputConfig {
  std::string dir = "/var/lib/slambooster";  // trajectory.tum, frames.jsonl, summary.json land here
  bool mesh = false;                         // also write mesh.ply of the final volume at exit
  bool modelPng = false;                     // also write model.png (the model rendered from the last pose)
  bool report = true;                        // write report.html (report/) at the end of each pass
  // The navigation map (navmap/, issue 45): a settings file (config/navmap.json keys: which way is up, the
  // robot's band); "" = none. Its map.pgm, map.yaml and map.bt are written into the pass's directory
  // atomically every navmapPeriodS seconds and at the end, and ?MAP answers the grid.
  std::string navmap;
  double navmapPeriodS = 10.0;
  // The map kept across restarts (issue 55; docs/map-store.md): a store directory every pass continues (it
  // localises in the map already there first); "" = none. Its slab files at most mapStoreKeepMib (0: no limit).
  std::string mapStore;
  double mapStoreKeepMib = 0.0;
  RotationConfig rotation;                   // per-frame outputs of long sessions
};

// Where the package installs the power meter's settings. At this default path a missing file means no meter
// (a development checkout has none); a file named explicitly must exist.
inline constexpr const char* kDefaultPowerConfig = "/etc/slambooster/power.json";

struct PowerRefConfig {
  std::string config = kDefaultPowerConfig;  // power meter config (config/power.json keys); empty = no energy
};

struct SocketConfig {
  std::string path = "/run/slambooster/slambooster.sock";  // ignored under socket activation
  unsigned mode = 0660;                                    // permission bits of the socket file
  std::string controlGroup;           // members may send ?CONTROL (besides root and the daemon's user)
  size_t maxClients = 128;            // further connections get an ERROR and are closed
  size_t maxClientsPerUid = 32;       // per unprivileged uid; privileged clients have reserved slots too
  size_t maxRequestBytes = 4096;      // longer request lines are refused with ERROR
  size_t clientBufferBytes = 262144;  // queued output per client; messages beyond it are dropped
  double clientStallSeconds = 5.0;    // a client that keeps its buffer full this long is disconnected
};

struct DaemonConfig {
  SourceConfig source;
  SlamConfig slam;
  OutputConfig output;
  SocketConfig socket;
  PowerRefConfig power;
  double statusIntervalSeconds = 1.0;  // sd_notify STATUS= updates
  std::string logLevel = "info";       // trace, debug, info, warn, error
};

// Reads `j` on top of the defaults. Unknown keys, wrong types and out-of-range values throw ConfigError
// naming `where`, the key, the value and what is allowed.
DaemonConfig parseDaemonConfig(const nlohmann::json& j, const std::string& where = "config");

// Applies one override "section.key=value" (value: JSON, or a plain string) to `j`. Throws ConfigError.
void applyOverride(nlohmann::json& j, const std::string& assignment);


// The whole config as JSON (the keys parseDaemonConfig reads).
nlohmann::json daemonConfigToJson(const DaemonConfig& config);

}  // namespace sb::daemon
