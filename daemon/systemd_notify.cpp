#include "daemon/systemd_notify.h"

#include <spdlog/spdlog.h>
#include <systemd/sd-daemon.h>

#include <cstdlib>
#include <cstring>

namespace sb::daemon {

SystemdNotifier::SystemdNotifier() {
  const char* socket = std::getenv("NOTIFY_SOCKET");
  enabled_ = socket && *socket;
  uint64_t usec = 0;
  if (sd_watchdog_enabled(0, &usec) > 0 && usec > 0) watchdogPeriod_ = std::chrono::microseconds(usec / 2);
}

void SystemdNotifier::send(const std::string& message) const {
  if (!enabled_) return;
  const int r = sd_notify(0, message.c_str());
  if (r < 0) spdlog::warn("sd_notify failed: {}", std::strerror(-r));
}

void SystemdNotifier::ready(const std::string& status) const {
  send("READY=1\nSTATUS=" + status);
}
void SystemdNotifier::status(const std::string& status) const {
  send("STATUS=" + status);
}
void SystemdNotifier::watchdog() const {
  send("WATCHDOG=1");
}
void SystemdNotifier::reloading() const {
  send("RELOADING=1");
}
void SystemdNotifier::stopping(const std::string& status) const {
  send("STOPPING=1\nSTATUS=" + status);
}

}  // namespace sb::daemon
