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
#include <functional>
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

  enum class ReadResult { open, closed };
  // Reads what the socket holds. Calls onLine(line) for every complete request line (without '\n') and
  // onOversize() once for every line longer than the cap (the rest of that line is discarded).
  ReadResult read(const std::function<void(std::string_view)>& onLine,
                  const std::function<void()>& onOversize);

  // Queues one line; false (and counted) when it does not fit in the budget.
  bool send(Line line);
  // Writes as much queued output as the socket takes. False when the peer is gone.
  bool flush();
  bool hasPendingOutput() const { return !queue_.empty(); }
  size_t queuedBytes() const { return queuedBytes_; }
  uint64_t dropped() const { return dropped_; }
  // Since when messages are being dropped without the client draining its queue (nullopt: not stalled).
  std::optional<SteadyClock::time_point> stalledSince() const { return stalledSince_; }

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
  std::deque<Line> queue_;
  size_t headOffset_ = 0;  // bytes of queue_.front() already written
  size_t queuedBytes_ = 0;
  uint64_t dropped_ = 0;
  std::optional<SteadyClock::time_point> stalledSince_;
};

}  // namespace sb::daemon
