#pragma once
// sd_notify(3) messages to the service manager: READY=1, STATUS=, WATCHDOG=1, STOPPING=1, RELOADING=1.
// Every call is a no-op when the daemon does not run under systemd (no NOTIFY_SOCKET).

#include <chrono>
#include <optional>
#include <string>

namespace sb::daemon {

class SystemdNotifier {
 public:
  SystemdNotifier();
  bool enabled() const { return enabled_; }
  // How often to send WATCHDOG=1 (half of WatchdogSec), or nullopt when the watchdog is off.
  std::optional<std::chrono::microseconds> watchdogPeriod() const { return watchdogPeriod_; }

  void ready(const std::string& status) const;
  void status(const std::string& status) const;
  void watchdog() const;
  void reloading() const;
  void stopping(const std::string& status) const;

 private:
  void send(const std::string& message) const;
  bool enabled_ = false;
  std::optional<std::chrono::microseconds> watchdogPeriod_;
};

}  // namespace sb::daemon
