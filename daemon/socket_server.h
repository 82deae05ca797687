#pragma once
// The protocol server on the event loop: accepts clients on a listening Unix stream socket, greets them
// with VERSION, answers requests (?WATCH ?POLL ?STATUS ?CONTROL ?VERSION), and fans out the reports the
// daemon publishes (POSE, KNOBS, ENERGY) to watching clients. Never blocks: a client that does not read
// loses messages and is then disconnected.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "daemon/client.h"
#include "daemon/daemon_config.h"
#include "daemon/event_loop.h"
#include "daemon/peer_auth.h"
#include "daemon/protocol.h"
#include "daemon/service_state.h"

namespace sb::daemon {

class SocketServer {
 public:
  // `listener`: a listening, non-blocking Unix stream socket (borrowed; see unix_socket.h).
  SocketServer(EventLoop& loop, int listener, const SocketConfig& config, ControlPolicy policy,
               ServiceState& state, std::string release);
  ~SocketServer();
  SocketServer(const SocketServer&) = delete;
  SocketServer& operator=(const SocketServer&) = delete;

  void publishFrame(const FrameReport& report);
  void publishEnergy(const EnergyReport& report);
  // Disconnects clients stalled longer than the configured limit. Call periodically.
  void dropStalledClients();

  size_t clientCount() const { return clients_.size(); }
  uint64_t messagesDropped() const { return messagesDropped_; }
  uint64_t clientsDisconnected() const { return clientsDisconnected_; }

 private:
  void accept();
  void onClientEvent(int fd, uint32_t events);
  void handleLine(Client& client, std::string_view line);
  void reply(Client& client, const nlohmann::json& message);
  void deliver(Client& client, const Line& line);
  void updateInterest(Client& client);
  void close(int fd, const char* why, bool byServer);
  nlohmann::json pollMessage() const;

  EventLoop& loop_;
  int listener_;
  SocketConfig config_;
  ControlPolicy policy_;
  ServiceState& state_;
  std::string release_;
  std::map<int, std::unique_ptr<Client>> clients_;
  std::optional<nlohmann::json> lastPose_, lastKnobs_, lastEnergy_;
  uint64_t framesPublished_ = 0;
  uint64_t messagesDropped_ = 0;
  uint64_t clientsDisconnected_ = 0;
};

}  // namespace sb::daemon
