#pragma once
// slamboosterd's top level: builds the parts in dependency order (source, SLAM worker, socket, event loop)
// and tears them down in reverse. Threads: capture (source -> queue), SLAM (queue -> pipeline -> outputs,
// reports), and the event loop (this thread: socket, signals, timers, sd_notify).
//
// Signals (blocked in every thread, read through a signalfd): SIGTERM/SIGINT finish the frame in hand, flush
// every output and exit 0; SIGHUP re-reads the controller settings.
//
// Energy: with power.config naming a meter, a PowerSampler thread reads it; the SLAM thread hands it every
// frame's interval and publishes each frame's joules as ENERGY (lagging POSE by up to one meter period). A
// meter that cannot be opened leaves the daemon running without energy (STATUS "meter_error").

#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include "daemon/daemon_config.h"
#include "daemon/protocol.h"
#include "daemon/service_state.h"
#include "odometry/odometry_input.h"

namespace sb {
struct SequenceInfo;
}

namespace sb::daemon {

class Mailbox;
class SlamWorker;

// What `slamboosterd --check-config` checks beyond the daemon config itself: the settings files it names
// (slam.pipeline_config, slam.controller_config, power.config) are read and validated as start-up would. The
// input and the devices are not opened. Throws ConfigError naming the key, the file and what is wrong.
void checkConfigFiles(const DaemonConfig& config);

// The paths and values of the source section that start-up would refuse (issue 53: --check-config said
// "valid" for them), checked by --check-config (through checkConfigFiles) and at start alike: a
// source.odometry file that is missing, a FIFO or a directory (an odometry.txt is read through), a
// source.camera_mount that is not a mount (odometry/camera_mount.h), a push source.path that exists and is not
// a socket. Throws ConfigError naming the key and the value.
void checkSourceFiles(const SourceConfig& source);

class Daemon : public ServiceState {
 public:
  // `reload` re-reads the configuration for SIGHUP (the same file and overrides); it throws sb::Error on a
  // bad file, and the daemon keeps its settings then.
  Daemon(DaemonConfig config, std::function<DaemonConfig()> reload, std::string release);
  ~Daemon() override;

  // Runs until SIGTERM/SIGINT (or the end of the input with source.at_end = "exit"). Returns the exit code:
  // 0 after a clean stop, 1 when the SLAM thread failed. Throws sb::Error when start-up fails.
  int run();

  // Any thread: a frame's energy is known (the meter ledger calls this; ENERGY may lag POSE).
  void publishEnergy(const EnergyReport& report);

  nlohmann::json status() override;
  nlohmann::json control(const ControlRequest& request) override;
  nlohmann::json odometry(const OdomRequest& request) override;

 private:
  // The odometry of source.odometry (odometry/odometry_input.h); the socket's live track when it takes ?ODOM.
  OdometryInput openDaemonOdometry();
  struct Parts;
  std::unique_ptr<SlamWorker> makeWorker(const SequenceInfo& info, Mailbox& mailbox);
  void onSignal();
  void onTimer();
  void reload();
  void startRetention();
  void startPower();
  void beginStop(const std::string& why);

  DaemonConfig config_;
  std::function<DaemonConfig()> reload_;
  std::string release_;
  std::chrono::steady_clock::time_point started_;
  std::unique_ptr<Parts> parts_;
  OdometryInput liveOdometry_;  // what ?ODOM adds to (shared with the SLAM thread); no track: ?ODOM refused
  bool stopping_ = false;
  bool workerDone_ = false;
};

}  // namespace sb::daemon
