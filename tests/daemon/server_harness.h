#pragma once
// Test support for the socket server: a SocketServer on a temporary socket with a scripted ServiceState,
// its event loop on a background thread, and a blocking line client.

#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "daemon/daemon_config.h"
#include "daemon/event_loop.h"
#include "core/unique_fd.h"
#include "daemon/mailbox.h"
#include "daemon/odom_intake.h"
#include "daemon/socket_server.h"
#include "daemon/unix_socket.h"

namespace sb::test {

// STATUS and CONTROL with fixed, scripted answers (golden outputs must not depend on time).
class ScriptedState : public daemon::ServiceState {
 public:
  nlohmann::json status() override;
  nlohmann::json control(const daemon::ControlRequest& request) override;
  // ?ODOM into a live track, as the daemon does (daemon/odom_intake.h).
  nlohmann::json odometry(const daemon::OdomRequest& request) override;
  std::vector<std::string> controls;  // what control() was asked, in order (event-loop thread)
  odometry::OdometryTrack odometryTrack;
};

// The deterministic frame report number n of the golden scripts.
daemon::FrameReport scriptedFrame(uint64_t n);

class ServerHarness {
 public:
  // `daemonUid`: the uid the ControlPolicy treats as the daemon's own.
  explicit ServerHarness(daemon::SocketConfig config = {}, uid_t daemonUid = static_cast<uid_t>(-2));
  ~ServerHarness();
  const std::string& path() const { return path_; }
  // Publishes on the event-loop thread (like the SLAM thread does through the mailbox).
  void publishFrame(const daemon::FrameReport& report);
  void publishEnergy(const EnergyReport& report);
  void publishMap(const daemon::MapReport& report);
  // Runs `fn` on the loop thread and waits for it.
  void sync(const std::function<void(daemon::SocketServer&)>& fn);
  ScriptedState state;

 private:
  std::string dir_;
  std::string path_;
  daemon::SocketConfig config_;
  daemon::EventLoop loop_;
  daemon::ListeningSocket listener_;
  std::unique_ptr<daemon::SocketServer> server_;
  std::unique_ptr<daemon::Mailbox> mailbox_;
  std::thread thread_;
};

class LineClient {
 public:
  explicit LineClient(const std::string& path);
  void send(const std::string& bytes);
  // The next line (without '\n'), or "" after `timeoutMs` / at EOF.
  std::string readLine(int timeoutMs = 5000);
  // True when the server closed the connection (EOF) within `timeoutMs`; lines before it are skipped.
  bool closedWithin(int timeoutMs);
  int fd() const { return fd_.get(); }
  void close() { fd_.reset(); }

 private:
  UniqueFd fd_;
  std::string buffer_;
  bool eof_ = false;
};

}  // namespace sb::test
