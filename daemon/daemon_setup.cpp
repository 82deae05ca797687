// Daemon's start-up steps beside the run (daemon.cpp): the retention store, the power meter, and what
// `slamboosterd --check-config` checks.

#include <spdlog/spdlog.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

#include "core/error.h"
#include "core/input_file.h"
#include "daemon/daemon.h"
#include "daemon/daemon_parts.h"
#include "daemon/peer_auth.h"
#include "odometry/camera_mount.h"
#include "odometry/odometry_file.h"
#include "runtime/energy_account.h"

namespace sb::daemon {

// The meter settings that power.config names; none when it is empty, or when the packaged default file is
// absent (a development checkout has none). Throws ConfigError naming the key.
std::optional<power::PowerConfig> loadPowerSettings(const PowerRefConfig& power) {
  if (power.config.empty()) return std::nullopt;
  if (power.config == kDefaultPowerConfig && !std::filesystem::exists(power.config)) return std::nullopt;
  try {
    return power::loadPowerConfig(power.config);
  } catch (const Error& e) {
    throw ConfigError(std::string("power.config: ") + e.what());
  }
}

// Retention: of the rotated outputs, and of the pass directories of a looping replay (one store for both).
void Daemon::startRetention() {
  Parts& p = *parts_;
  const bool rotating = rotates(config_.output.rotation, p.source->live());
  const bool looping = config_.source.atEnd == "loop";
  if (!rotating && !looping) return;
  std::error_code ec;
  std::filesystem::create_directories(config_.output.dir, ec);  // a failure is reported by the first output
  p.retention = std::make_shared<SegmentStore>(config_.output.dir, retentionLimits(config_.output.rotation));
  const RetentionLimits& l = p.retention->limits();
  if (rotating) {
    p.segments = p.retention;
    p.worker->setSegments(p.segments);
    spdlog::info("outputs rotated in {}: segments of {} MiB or {} s, {} MiB kept, {} MiB left free",
                 config_.output.dir, l.segmentBytes >> 20, l.segmentSeconds, l.keepBytes >> 20,
                 l.minFreeBytes >> 20);
  }
  if (looping) {
    p.worker->setPassRetention(p.retention);
    spdlog::info("pass directories in {}: the oldest removed past {} MiB{}, or with less than {} MiB free",
                 config_.output.dir, l.keepBytes >> 20,
                 l.keepSegments ? " or " + std::to_string(l.keepSegments) + " kept" : std::string(),
                 l.minFreeBytes >> 20);
  }
}

void Daemon::startPower() {
  Parts& p = *parts_;
  const std::optional<power::PowerConfig> loaded = loadPowerSettings(config_.power);
  if (!loaded) {
    if (!config_.power.config.empty())
      spdlog::info("no {}: no energy accounting (power.config names the meter's settings)",
                   kDefaultPowerConfig);
    return;
  }
  const power::PowerConfig& pc = *loaded;
  if (pc.meter == "none") return;
  try {
    std::filesystem::create_directories(config_.output.dir);
    p.sampler =
        openSampler(pc, config_.output.dir, p.segments);  // the meter and trace of `slambooster run --power`
    p.sampler->start();
  } catch (const std::exception& e) {
    // SLAM without energy beats no SLAM (a robot needs its poses); STATUS and the log say why.
    p.sampler.reset();
    p.meterError = std::string("meter '") + pc.meter + "' not in use: " + e.what();
    spdlog::error("{}; running without energy accounting", p.meterError);
    return;
  }
  const std::string name = p.sampler->meterInfo().name;
  spdlog::info("power meter {} on {}; raw trace {}/power.csv", name, p.sampler->meterInfo().device,
               config_.output.dir);
  p.worker->setPower(p.sampler.get(), [this, name](const power::FrameEnergy& e) {
    publishEnergy(EnergyReport{e.frame, e.joules, e.meanWatts, name});
  });
}

void Daemon::publishEnergy(const EnergyReport& report) {
  if (!parts_ || !parts_->mailbox) return;
  parts_->mailbox->post([this, report] { parts_->server->publishEnergy(report); });
}

void checkSourceFiles(const SourceConfig& source) {
  const std::string& odometry = source.odometry;
  if (odometry != "auto" && odometry != "none" && odometry != "socket") {
    if (const std::string problem = pathProblem(odometry); !problem.empty())
      throw ConfigError("source.odometry " + quoteForMessage(odometry) + " " + problem +
                        " (give \"auto\", \"socket\", \"none\" or the path of an odometry.txt or a .bag)");
  }
  if (!source.cameraMount.empty()) {
    try {
      odometry::parseCameraMount(source.cameraMount, "source.camera_mount");
    } catch (const Error& e) {
      throw ConfigError(e.what());
    }
  }
  if (source.type == "push" && !source.path.empty()) {
    struct stat st {};
    if (::lstat(source.path.c_str(), &st) == 0 && !S_ISSOCK(st.st_mode))
      throw ConfigError("source.path " + quoteForMessage(source.path) +
                        " exists and is not a socket (the push source listens there): remove it or set source.path");
  }
}

void checkConfigFiles(const DaemonConfig& config) {
  checkSourceFiles(config.source);
  const std::string& odometry = config.source.odometry;
  if (odometry != "auto" && odometry != "none" && odometry != "socket" &&
      std::filesystem::path(odometry).extension() != ".bag") {
    try {  // every line, as the start's reader checks it (odometry/odometry_file.h), one line in memory at a time
      odometry::checkOdometryFile(odometry);
    } catch (const Error& e) {
      throw ConfigError(std::string("source.odometry: ") + e.what());
    }
  }
  try {
    const PipelineConfig pipeline = buildPipelineConfig(config.slam, SequenceInfo{});
    buildOdometryConfig(config.slam);
    ControllerContext context;
    context.baseKnobs = pipeline.knobs;
    loadControllerSettings(config.slam, context);
    const ControlPolicy policy(::geteuid(),
                               config.socket.controlGroup);  // an unknown group fails as at start
    (void)policy;
  } catch (const ConfigError&) {
    throw;
  } catch (const Error& e) {
    throw ConfigError(e.what());
  }
  loadPowerSettings(config.power);
}

}  // namespace sb::daemon
