#pragma once
// One connected client of the socket: its input line buffer (with the request size cap), its bounded
// output queue, what it watches, and who it is. Owned and used by the event-loop thread only.
//
// Output is a queue of shared, immutable lines (one encoding per message, shared by every watcher). When a
// message does not fit in the client's budget it is dropped and counted; the server disconnects a client
// whose queue stays full for too long (SocketConfig::clientStallSeconds).

#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "core/unique_fd.h"
#include "daemon/peer_auth.h"

namespace sb::daemon {

using SteadyClock = std::chrono::steady_clock;
using Line = std::shared_ptr<const std::string>;

class Client {
 public:
  Client(UniqueFd fd, PeerCredentials peer, size_t maxRequestBytes, size_t maxQueuedBytes);

  int fd() const { return fd_.get(); }
  const PeerCredentials& peer() const { return peer_; }

  // One request line read and not yet served: its text (without '\n' and a '\r' before it), or a line
  // longer than the cap (refused with ERROR; the rest of that line is discarded).
  struct PendingLine {
    std::string text;
    bool oversize = false;
  };
  // At most this many request lines wait per client: the socket is not read again until they are served,
  // so a flooding client's requests wait in its own socket buffer, not in the daemon.
  static constexpr size_t kMaxPendingLines = 64;

  enum class ReadResult { open, closed };
  // Reads what the socket holds into the pending lines (while fewer than kMaxPendingLines wait). `closed`
  // once the peer has closed and every line it sent has been served.
  ReadResult read();
  bool hasPendingLines() const { return !lines_.empty(); }
  // The oldest pending line (hasPendingLines() must be true).
  PendingLine takeLine();
  // Whether the socket should be read now (room for lines, the peer not yet closed).
  bool wantsInput() const { return !peerClosed_ && lines_.size() < kMaxPendingLines; }
  bool peerClosed() const { return peerClosed_; }

  // Queues one line; false (and counted) when it does not fit in the budget.
  bool send(Line line);
  // Writes as much queued output as the socket takes. False when the peer is gone.
  bool flush();
  bool hasPendingOutput() const { return !queue_.empty(); }
  uint64_t dropped() const { return dropped_; }
  // Since when messages are being dropped without the client draining its queue (nullopt: not stalled).
  std::optional<SteadyClock::time_point> stalledSince() const { return stalledSince_; }

  // The last MAP (or CLOUD) this client was sent and when: a repeat of the same line within
  // SocketServer::kSameBulkReplyInterval is refused (the rate limit of ?MAP and ?CLOUD).
  struct BulkSent {
    Line line;
    SteadyClock::time_point at;
  };
  BulkSent lastMap, lastCloud;
  // Until when the client's further request lines wait (a rate limit's refusal: its retry_after_s).
  SteadyClock::time_point heldUntil;
  bool held(SteadyClock::time_point now) const { return now < heldUntil; }

  // What the client asked for with ?WATCH.
  bool watching = false;
  bool watchPose = true;
  bool watchKnobs = true;
  bool watchEnergy = true;

 private:
  UniqueFd fd_;
  PeerCredentials peer_;
  const size_t maxRequestBytes_;
  const size_t maxQueuedBytes_;
  std::string input_;
  bool discarding_ = false;  // inside an oversize line: drop bytes up to the next '\n'
  bool peerClosed_ = false;  // recv() returned 0: serve what is pending, then close
  std::deque<PendingLine> lines_;
  std::deque<Line> queue_;
  size_t headOffset_ = 0;  // bytes of queue_.front() already written
  size_t queuedBytes_ = 0;
  uint64_t dropped_ = 0;
  std::optional<SteadyClock::time_point> stalledSince_;
};

}  // namespace sb::daemon
