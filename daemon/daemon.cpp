#include "daemon/daemon.h"

#include <signal.h>
#include <spdlog/spdlog.h>
#include <sys/signalfd.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "core/error.h"
#include "core/input_file.h"
#include "daemon/daemon_parts.h"
#include "daemon/fd_budget.h"
#include "daemon/odom_intake.h"
#include "daemon/peer_auth.h"
#include "daemon/source_registry.h"
#include "power/energy_json.h"
#include "runtime/map_slabs.h"

namespace sb::daemon {

namespace {

using Clock = std::chrono::steady_clock;
constexpr auto kTick = std::chrono::milliseconds(250);  // housekeeping period (stalled clients, STATUS=)
constexpr size_t kMailboxCapacity = 4096;               // reports in flight to the event loop

sigset_t handledSignals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGHUP);
  return set;
}

UniqueFd makeTimer(std::chrono::nanoseconds period) {
  UniqueFd fd(timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC));
  if (!fd.valid()) throw Error(std::string("timerfd_create failed: ") + std::strerror(errno));
  itimerspec spec{};
  spec.it_interval.tv_sec = static_cast<time_t>(period.count() / 1000000000);
  spec.it_interval.tv_nsec = static_cast<long>(period.count() % 1000000000);
  spec.it_value = spec.it_interval;
  timerfd_settime(fd.get(), 0, &spec, nullptr);
  return fd;
}

// STATUS "disk": the outputs' bytes on disk and the file system's free space. With a retention store
// (rotation, or a looping replay) the store counts every segment and ended pass directory under output.dir;
// without one the files of the current pass's directory are summed. Either way the slab files of the current
// pass's map (map_slabs/) are in `bytes` and, alone, in `slab_bytes` and `slab_files`.
nlohmann::json diskStatus(const SegmentStore* retention, bool rotating, const std::string& dir) {
  const MapSlabFiles slabs = mapSlabFiles(dir);
  if (retention) {
    const SegmentUsage u = retention->usage();
    return {{"rotation", rotating},      {"bytes", u.bytes + slabs.bytes},
            {"free_bytes", u.freeBytes}, {"limit_bytes", u.keepBytes},
            {"segments", u.segments},    {"removed_segments", u.removedSegments},
            {"slab_bytes", slabs.bytes}, {"slab_files", slabs.files}};
  }
  uint64_t bytes = slabs.bytes;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec))
    if (entry.is_regular_file(ec)) {
      const uintmax_t size = entry.file_size(ec);
      if (!ec) bytes += size;
    }
  const std::filesystem::space_info space = std::filesystem::space(dir, ec);
  return {{"rotation", false},
          {"bytes", bytes},
          {"free_bytes", ec ? 0 : space.available},
          {"slab_bytes", slabs.bytes},
          {"slab_files", slabs.files}};
}

}  // namespace

Daemon::Daemon(DaemonConfig config, std::function<DaemonConfig()> reload, std::string release)
    : config_(std::move(config)),
      reload_(std::move(reload)),
      release_(std::move(release)),
      started_(Clock::now()) {}

Daemon::~Daemon() = default;

std::unique_ptr<SlamWorker> Daemon::makeWorker(const SequenceInfo& info, Mailbox& mailbox) {
  return std::make_unique<SlamWorker>(
      config_, info, *parts_->queue,
      [this, &mailbox](FrameReport report) {
        mailbox.post([this, r = std::move(report)] {
          // The frames' clock, against which ?ODOM's stamps are placed (odometry_track.h's leap rule).
          if (liveOdometry_.track) liveOdometry_.track->noteFrameStamp(r.pose.timestamp);
          parts_->server->publishFrame(r);
        });
      },
      [this, &mailbox] {
        mailbox.post([this] {
          workerDone_ = true;
          const WorkerStats s = parts_->worker->stats();
          const bool inputFailed = !parts_->capture.error().empty();
          // A failed input (a truncated PNG) with at_end stop or loop keeps serving, as an ended one does:
          // STATUS says "failed" with the error until SIGTERM (exit 1). A failed SLAM thread exits.
          if (stopping_ || (s.state == "failed" && !inputFailed) || config_.source.atEnd == "exit") {
            parts_->loop.stop();
          } else if (s.state == "failed") {
            spdlog::error("input failed after {} frames; outputs flushed; still serving the socket", s.frames);
            parts_->notifier.status("failed after " + std::to_string(s.frames) + " frames: " + sb::printable(s.error, 200));
          } else {
            spdlog::info("input ended after {} frames; outputs flushed; still serving the socket", s.frames);
            parts_->notifier.status("input ended after " + std::to_string(s.frames) + " frames");
          }
        });
      });
}

int Daemon::run() {
  // Blocked before any thread starts, so that every thread inherits the mask and only the signalfd sees them.
  const sigset_t set = handledSignals();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  signal(SIGPIPE, SIG_IGN);

  parts_ = std::make_unique<Parts>();
  Parts& p = *parts_;
  const size_t fdLimit = ensureFdBudget(config_.socket.maxClients);  // before any file is opened
  spdlog::debug("open-file limit {}: {} clients plus {} for the pipeline", fdLimit, config_.socket.maxClients,
                kReservedFds + 1);
  checkSourceFiles(config_.source);  // what --check-config checks of the source, the same way
  SourceConfig source = config_.source;
  source.socketMode = config_.socket.mode;  // the push socket follows the control socket's mode
  p.source = createSource(source);
  const SequenceInfo info = p.source->info();
  p.queue = std::make_unique<FrameQueue>(
      config_.source.queueFrames, p.source->live() ? FrameQueue::Policy::newest : FrameQueue::Policy::wait);
  p.mailbox = std::make_unique<Mailbox>(p.loop, kMailboxCapacity);
  Mailbox& mailbox = *p.mailbox;
  try {
    p.worker = makeWorker(info, mailbox);
    p.worker->setOdometry(openDaemonOdometry());
    p.worker->setMapPublish([this, &mailbox](MapReport report) {  // the grid, for ?MAP (output.navmap)
      mailbox.post([this, r = std::move(report)] { parts_->server->publishMap(r); });
    });
  } catch (const ConfigError&) {
    throw;
  } catch (const Error& e) {
    throw ConfigError(e.what());  // the pipeline config file or the controller settings
  }
  startRetention();
  startPower();
  p.listener = openListeningSocket(config_.socket.path, config_.socket.mode);
  p.server = std::make_unique<SocketServer>(p.loop, p.listener.fd.get(), config_.socket,
                                            ControlPolicy(::geteuid(), config_.socket.controlGroup), *this,
                                            release_);

  p.signals.reset(signalfd(-1, &set, SFD_NONBLOCK | SFD_CLOEXEC));
  if (!p.signals.valid()) throw Error(std::string("signalfd failed: ") + std::strerror(errno));
  p.loop.add(p.signals.get(), EPOLLIN, [this](uint32_t) { onSignal(); });
  auto tick = std::chrono::duration_cast<std::chrono::nanoseconds>(kTick);
  if (p.notifier.watchdogPeriod())
    tick = std::min(tick, std::chrono::duration_cast<std::chrono::nanoseconds>(*p.notifier.watchdogPeriod()));
  p.timer = makeTimer(tick);
  p.loop.add(p.timer.get(), EPOLLIN, [this](uint32_t) { onTimer(); });

  p.worker->start();
  p.capture.start(*p.source, *p.queue);

  spdlog::info("slamboosterd {} serving {} ({}); input {} ({} frames)", release_, p.listener.path,
               p.listener.activated ? std::string("socket activation")
                                    : fmt::format("mode {:04o}", config_.socket.mode),
               info.path, info.frameCount);
  p.notifier.ready("replaying " + info.path);

  p.loop.run();

  // Reverse order of start-up: input, SLAM thread (flushes its outputs), socket.
  p.source->stop();
  p.queue->abort();
  p.capture.join();
  p.worker->join();
  const WorkerStats s = p.worker->stats();
  const std::string captureError = p.capture.error();
  p.notifier.stopping("stopped after " + std::to_string(s.frames) + " frames");
  p.server.reset();
  spdlog::info("stopped after {} frames; outputs in {}", s.frames, s.outputDir);
  return s.state == "failed" || !captureError.empty() ? 1 : 0;
}

void Daemon::beginStop(const std::string& why) {
  if (stopping_) return;
  stopping_ = true;
  spdlog::info("{}: finishing the current frame and flushing the outputs", why);
  parts_->notifier.stopping(why);
  parts_->worker->requestStop();
  parts_->source->stop();
  parts_->queue->abort();
  if (workerDone_) parts_->loop.stop();
}

void Daemon::onSignal() {
  signalfd_siginfo info{};
  while (::read(parts_->signals.get(), &info, sizeof info) == static_cast<ssize_t>(sizeof info)) {
    if (info.ssi_signo == SIGHUP) {
      reload();
    } else {
      beginStop(info.ssi_signo == SIGTERM ? "SIGTERM" : "SIGINT");
    }
  }
}

void Daemon::reload() {
  Parts& p = *parts_;
  p.notifier.reloading();
  try {
    const DaemonConfig fresh = reload_();
    ControllerSettings settings = loadControllerSettings(fresh.slam, p.worker->controllerContext());
    nlohmann::json before = daemonConfigToJson(config_), after = daemonConfigToJson(fresh);
    before["slam"].erase("controller");
    before["slam"].erase("controller_config");
    after["slam"].erase("controller");
    after["slam"].erase("controller_config");
    before.erase("log_level");
    after.erase("log_level");
    if (before != after)
      spdlog::warn("SIGHUP: only the controller settings are reloaded; restart for the other changes");
    p.worker->switchController(settings, settings.name);
    config_.slam.controller = fresh.slam.controller;
    config_.slam.controllerConfig = fresh.slam.controllerConfig;
    spdlog::info("SIGHUP: controller settings reloaded; controller '{}' from the next frame", settings.name);
  } catch (const std::exception& e) {
    spdlog::error("SIGHUP: reload failed, settings unchanged: {}", sb::printable(e.what()));
  }
  p.notifier.ready("running");
}

void Daemon::onTimer() {
  Parts& p = *parts_;
  uint64_t expirations = 0;
  (void)!::read(p.timer.get(), &expirations, sizeof expirations);
  p.server->dropStalledClients();
  p.server->resumeAccepting();
  const auto now = Clock::now();
  const WorkerStats s = p.worker->stats();
  if (p.notifier.watchdogPeriod()) {
    // Alive means: not stuck on one frame for longer than WatchdogSec (twice the ping period).
    const bool stuck = s.busySince && now - *s.busySince > 2 * *p.notifier.watchdogPeriod();
    if (!stuck) {
      p.notifier.watchdog();
      p.watchdogWarned = false;
    } else if (!p.watchdogWarned) {
      spdlog::error("watchdog: the SLAM thread has been on one frame for too long; not pinging systemd");
      p.watchdogWarned = true;
    }
  }
  if (now - p.lastStatus >= std::chrono::duration<double>(config_.statusIntervalSeconds)) {
    p.lastStatus = now;
    char text[160];
    std::snprintf(text, sizeof text, "%s: %llu frames, %.1f fps, %.1f ms/frame, controller %s, %zu clients",
                  s.state.c_str(), static_cast<unsigned long long>(s.frames), s.fps, s.computationMs,
                  s.controller.c_str(), p.server->clientCount());
    p.notifier.status(text);
  }
}

nlohmann::json Daemon::status() {
  Parts& p = *parts_;
  const WorkerStats s = p.worker->stats();
  nlohmann::json source = p.source->status();
  source["queued"] = p.queue->size();
  source["dropped"] = p.queue->dropped();
  std::string state = stopping_ ? "stopping" : s.state;
  nlohmann::json j = {{"state", state},
                      {"source", source},
                      {"controller", s.controller},
                      {"pinned", s.pinned},
                      {"meter", p.sampler ? p.sampler->meterInfo().name : std::string("none")},
                      {"fps", s.fps},
                      {"frames", s.frames},
                      {"tracked", s.tracked},
                      {"tracking_state", {{"current", s.trackingState},
                                          {"lost_frames", s.lostFrames},
                                          {"lost_stretches", s.lostStretches},
                                          {"relocalisations", s.relocalisations}}},
                      {"odometry", {{"frames", s.odometryFrames},
                                    {"missing", s.odometryMissing},
                                    {"rejected", s.odometryRejected},
                                    {"odometry_only", s.odometryOnlyFrames},
                                    {"why", s.odometryWhy}}},
                      {"computation_ms", s.computationMs},
                      {"drops", p.queue->dropped() + p.mailbox->dropped()},
                      {"uptime_s", std::chrono::duration<double>(Clock::now() - started_).count()},
                      {"cpus", s.cpus},
                      {"threads", s.threads},
                      {"pass", s.pass},
                      {"output_dir", s.outputDir}};
  if (!s.keptMap.empty()) j["kept_map"] = s.keptMap;  // protocol 1.11
  if (const std::string e = p.capture.error(); !e.empty()) j["error"] = e;
  if (!s.error.empty()) j["error"] = s.error;
  if (!p.meterError.empty()) j["meter_error"] = p.meterError;
  j["disk"] = diskStatus(p.retention.get(), p.segments != nullptr,
                         s.outputDir.empty() ? config_.output.dir : s.outputDir);
  if (p.sampler) {
    const power::MeterStatus m = p.sampler->meterStatus();
    nlohmann::json energy = power::energyTotalsJson(p.sampler->totals(), {});
    energy.erase("unknown_reasons");
    energy["connected"] = m.connected;
    energy["device"] = p.sampler->meterInfo().device;
    if (!m.message.empty()) energy["message"] = m.message;
    j["energy"] = energy;
  }
  return j;
}

OdometryInput Daemon::openDaemonOdometry() {
  const SourceConfig& c = config_.source;
  OdometryInput in;
  if (c.odometry != "socket")
    in = openOdometry(c.odometry, c.type == "replay" ? c.path : std::string(),
                      BagOdometryOptions{c.odomTopic, c.cameraMount});
  if (!in.track && (c.odometry == "auto" || c.odometry == "socket")) {
    liveOdometry_ = liveOdometry("socket");
    in = liveOdometry_;
  }
  if (in.track) spdlog::info("odometry: {} ({} samples)", in.source, in.track->size());
  return in;
}

nlohmann::json Daemon::odometry(const OdomRequest& request) {
  if (!liveOdometry_.track)
    throw Error(config_.source.odometry == "none"
                    ? "?ODOM: this daemon takes no odometry (source.odometry is \"none\")"
                    : "?ODOM: this daemon's odometry comes from " + config_.source.odometry +
                          " (source.odometry \"socket\" or \"auto\" without a file takes ?ODOM)");
  return addOdomSamples(*liveOdometry_.track, request);
}

nlohmann::json Daemon::control(const ControlRequest& request) {
  Parts& p = *parts_;
  if (request.controller) {
    try {  // validate the name before anything changes
      createController(*request.controller, p.worker->controllerSettings(), p.worker->controllerContext());
    } catch (const Error& e) {
      throw Error(std::string("?CONTROL: ") + e.what());
    }
  }
  nlohmann::json pinned;
  try {
    pinned = p.worker->changePins(request);
  } catch (const Error& e) {
    throw Error(std::string("?CONTROL: ") + e.what());
  }
  if (request.controller) p.worker->switchController(p.worker->controllerSettings(), *request.controller);
  return {{"ok", true},
          {"controller", request.controller ? *request.controller : p.worker->stats().controller},
          {"pinned", pinned}};
}

}  // namespace sb::daemon
