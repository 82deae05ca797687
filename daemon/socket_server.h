#pragma once
// The protocol server on the event loop: accepts clients on a listening Unix stream socket, greets them
// with VERSION, answers requests (?WATCH ?POLL ?STATUS ?CONTROL ?VERSION), and fans out the reports the
// daemon publishes (POSE, KNOBS, ENERGY) to watching clients. Never blocks: a client that does not read
// loses messages and is then disconnected.

#include <chrono>
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
  // Client slots kept for privileged peers (at most a quarter of socket.max_clients).
  static constexpr size_t kPrivilegedSlots = 4;
  // Requests served per event-loop turn: per client, per uid (all its connections), and in all. A turn
  // serves at most kRequestsPerTurn requests, so the loop gets back to the POSE fan-out within a few ms.
  static constexpr size_t kRequestsPerClientPerTurn = 8;
  static constexpr size_t kRequestsPerUidPerTurn = 32;
  static constexpr size_t kRequestsPerTurn = 128;
  // The rate limit of the bulky replies (issue 53): a connection is sent the same MAP (or CLOUD) at most once
  // per this interval. Asking again sooner gets ERROR with retry_after_s (docs/protocol.md); a new grid is
  // always sent. A flood of ?MAP then costs what a flood of short replies costs, not a grid per request.
  static constexpr std::chrono::milliseconds kSameBulkReplyInterval{1000};

  // `listener`: a listening, non-blocking Unix stream socket (borrowed; see unix_socket.h).
  SocketServer(EventLoop& loop, int listener, const SocketConfig& config, ControlPolicy policy,
               ServiceState& state, std::string release);
  ~SocketServer();
  SocketServer(const SocketServer&) = delete;
  SocketServer& operator=(const SocketServer&) = delete;

  void publishFrame(const FrameReport& report);
  void publishEnergy(const EnergyReport& report);
  // The navigation grid the SLAM thread last wrote: ?MAP answers it, ?CLOUD its cloud (encoded once, shared by
  // every reply).
  void publishMap(const MapReport& report);
  // Disconnects clients stalled longer than the configured limit. Call periodically.
  void dropStalledClients();
  // Listens again after accept() failed for lack of descriptors (it pauses rather than spin). The daemon
  // calls it once per housekeeping tick; a client leaving calls it too.
  void resumeAccepting();

  size_t clientCount() const { return clients_.size(); }
  uint64_t messagesDropped() const { return messagesDropped_; }
  uint64_t clientsDisconnected() const { return clientsDisconnected_; }
  // Times accept() failed for lack of descriptors or memory and the listener was paused.
  uint64_t acceptPauses() const { return acceptPauses_; }

 private:
  void accept();
  // Why an unprivileged `peer` may not connect now (the privileged reserve, the per-uid cap), or "".
  std::string refusal(const PeerCredentials& peer) const;
  // Sends ERROR "<why>; try again later" on `fd` without blocking (the caller closes it).
  void refuse(UniqueFd& fd, const std::string& why);
  void pauseAccepting(int error);
  void onClientEvent(int fd, uint32_t events);
  // Serves the clients' pending request lines within this turn's budgets; true while some still wait.
  bool serveRequests();
  void handleLine(Client& client, std::string_view line);
  void reply(Client& client, const nlohmann::json& message);
  void deliver(Client& client, const Line& line);
  // `line` (the MAP or CLOUD asked by `request`, `what` it holds) unless `sent` says this client got it less
  // than kSameBulkReplyInterval ago; then the ERROR saying when to ask again.
  void deliverBulk(Client& client, const Line& line, Client::BulkSent& sent, const char* request,
                   const char* what);
  void updateInterest(Client& client);
  void close(int fd, const char* why, bool byServer);
  nlohmann::json pollMessage() const;
  nlohmann::json permissionDenied(const Client& client) const;

  EventLoop& loop_;
  int listener_;
  SocketConfig config_;
  ControlPolicy policy_;
  ServiceState& state_;
  std::string release_;
  std::map<int, std::unique_ptr<Client>> clients_;
  std::optional<nlohmann::json> lastPose_, lastKnobs_, lastEnergy_;
  Line lastMap_;  // MAP, or null before the first grid
  Line lastCloud_;  // CLOUD, or null before the first grid with a cloud
  uint64_t framesPublished_ = 0;
  uint64_t messagesDropped_ = 0;
  uint64_t clientsDisconnected_ = 0;
  uint64_t acceptPauses_ = 0;
  bool acceptPaused_ = false;
  int lastFirstServed_ = -1;  // the client served first in the last turn (round robin)
};

}  // namespace sb::daemon
