#pragma once
// Daemon's parts (daemon.h), shared by daemon.cpp (the run and the event-loop handlers) and daemon_setup.cpp
// (the start-up steps). Private to those two files.

#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "core/segment_store.h"
#include "core/unique_fd.h"
#include "daemon/capture_thread.h"
#include "daemon/daemon.h"
#include "daemon/event_loop.h"
#include "daemon/frame_queue.h"
#include "daemon/mailbox.h"
#include "daemon/slam_worker.h"
#include "daemon/socket_server.h"
#include "daemon/systemd_notify.h"
#include "daemon/unix_socket.h"
#include "power/power_config.h"
#include "power/power_sampler.h"

namespace sb::daemon {

struct Daemon::Parts {
  SystemdNotifier notifier;
  std::unique_ptr<CaptureSource> source;
  std::unique_ptr<FrameQueue> queue;
  EventLoop loop;
  std::unique_ptr<Mailbox> mailbox;
  ListeningSocket listener;
  std::unique_ptr<SocketServer> server;
  std::shared_ptr<SegmentStore> segments;        // rotation and retention of the outputs (nullptr: none)
  std::shared_ptr<SegmentStore> retention;       // `segments`, or the pass directories' of a looping replay
  std::unique_ptr<power::PowerSampler> sampler;  // before the worker: destroyed after it
  std::string meterError;                        // why the configured meter is not in use
  std::unique_ptr<SlamWorker> worker;  // holds the controller settings (read once, at its construction)
  CaptureThread capture;
  UniqueFd signals, timer;
  std::chrono::steady_clock::time_point lastStatus = std::chrono::steady_clock::now();
  bool watchdogWarned = false;
};

// The meter settings that power.config names; none when it is empty, or when the packaged default file is
// absent (a development checkout has none). Throws ConfigError naming the key.
std::optional<power::PowerConfig> loadPowerSettings(const PowerRefConfig& power);

}  // namespace sb::daemon
