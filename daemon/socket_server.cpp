#include "daemon/socket_server.h"

#include <spdlog/spdlog.h>
#include <sys/socket.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cerrno>
#include <cstring>
#include <vector>

#include "core/error.h"

namespace sb::daemon {

namespace {

Line makeLine(const nlohmann::json& message) {
  return std::make_shared<const std::string>(toLine(message));
}

}  // namespace

SocketServer::SocketServer(EventLoop& loop, int listener, const SocketConfig& config, ControlPolicy policy,
                           ServiceState& state, std::string release)
    : loop_(loop),
      listener_(listener),
      config_(config),
      policy_(std::move(policy)),
      state_(state),
      release_(std::move(release)) {
  loop_.add(listener_, EPOLLIN, [this](uint32_t) { accept(); });
  loop_.setAfterTurn([this] { return serveRequests(); });
}

SocketServer::~SocketServer() {
  loop_.setAfterTurn(nullptr);
  for (auto& [fd, client] : clients_) {
    client->flush();  // best effort: the last messages to clients that read
    loop_.remove(fd);
  }
  loop_.remove(listener_);
}

void SocketServer::accept() {
  while (true) {
    UniqueFd fd(accept4(listener_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC));
    if (!fd.valid()) {
      if (errno == EINTR || errno == ECONNABORTED) continue;
      if (errno == EAGAIN || errno == EWOULDBLOCK) return;
      // Out of descriptors (EMFILE, ENFILE) or memory: the connection stays queued and epoll would report it
      // again at once. Stop listening until the next housekeeping tick or until a client leaves.
      pauseAccepting(errno);
      return;
    }
    if (clients_.size() >= config_.maxClients) {
      refuse(fd, "too many clients (limit " + std::to_string(config_.maxClients) + ", socket.max_clients)");
      continue;  // fd closes here
    }
    PeerCredentials peer;
    try {
      peer = peerCredentials(fd.get());
    } catch (const Error& e) {
      spdlog::warn("socket: {}; connection refused", e.what());
      continue;
    }
    if (const std::string why = refusal(peer); !why.empty()) {
      refuse(fd, why);
      continue;
    }
    const int raw = fd.get();
    auto client = std::make_unique<Client>(std::move(fd), std::move(peer), config_.maxRequestBytes,
                                           config_.clientBufferBytes);
    Client& c = *client;
    clients_.emplace(raw, std::move(client));
    loop_.add(raw, EPOLLIN, [this, raw](uint32_t events) { onClientEvent(raw, events); });
    spdlog::debug("socket: client fd {} connected (pid {}, uid {})", raw, c.peer().pid, c.peer().uid);
    reply(c, versionMessage(release_));
  }
}

std::string SocketServer::refusal(const PeerCredentials& peer) const {
  if (policy_.allowed(peer)) return "";  // privileged: only the total limit applies
  // One user cannot lock out root: the last slots are kept for privileged clients.
  const size_t reserved = std::min<size_t>(kPrivilegedSlots, config_.maxClients / 4);
  if (clients_.size() + reserved >= config_.maxClients)
    return "too many clients (limit " + std::to_string(config_.maxClients) +
           ", socket.max_clients; the last " + std::to_string(reserved) + " are kept for privileged clients)";
  size_t same = 0;
  for (const auto& [fd, client] : clients_) same += client->peer().uid == peer.uid;
  if (same >= config_.maxClientsPerUid)
    return "too many clients for uid " + std::to_string(peer.uid) + " (limit " +
           std::to_string(config_.maxClientsPerUid) + ", socket.max_clients_per_uid)";
  return "";
}

void SocketServer::refuse(UniqueFd& fd, const std::string& why) {
  const std::string line = toLine(errorMessage(why + "; try again later"));
  (void)!::send(fd.get(), line.data(), line.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
  ++clientsDisconnected_;
}

void SocketServer::onClientEvent(int fd, uint32_t events) {
  auto it = clients_.find(fd);
  if (it == clients_.end()) return;
  Client& client = *it->second;
  if (events & EPOLLOUT) {
    if (!client.flush()) return close(fd, "write failed", false);
  }
  if (events & (EPOLLIN | EPOLLHUP | EPOLLERR)) {
    // Only reads: the lines are served after this turn's events (serveRequests), within budgets.
    if (client.read() == Client::ReadResult::closed) return close(fd, "peer closed", false);
  }
  updateInterest(client);
}

bool SocketServer::serveRequests() {
  // Budgets per turn: a flooding client, or many connections of one uid, get a bounded share of each turn,
  // so the POSE fan-out (posted to the loop between turns) never waits behind them.
  std::map<uid_t, size_t> servedPerUid;
  size_t served = 0;
  std::vector<int> ready;
  const auto now = SteadyClock::now();
  // A held client (refused by a rate limit) waits: its lines are looked at again at a later turn (every POSE
  // and the daemon's housekeeping tick make one), without keeping the loop busy meanwhile.
  for (const auto& [fd, client] : clients_)
    if (client->hasPendingLines() && !client->held(now)) ready.push_back(fd);
  if (ready.empty()) return false;
  // Start after the last client served first, so no client is always first (or always cut off).
  const auto first = std::upper_bound(ready.begin(), ready.end(), lastFirstServed_);
  std::rotate(ready.begin(), first, ready.end());
  lastFirstServed_ = ready.front();
  bool pending = false;
  for (const int fd : ready) {
    Client& client = *clients_.at(fd);
    size_t& uidServed = servedPerUid[client.peer().uid];
    for (size_t n = 0; client.hasPendingLines() && !client.held(now) && n < kRequestsPerClientPerTurn &&
                       uidServed < kRequestsPerUidPerTurn && served < kRequestsPerTurn;
         ++n, ++uidServed, ++served) {
      const Client::PendingLine line = client.takeLine();
      if (line.oversize)
        reply(client, errorMessage("request longer than " + std::to_string(config_.maxRequestBytes) +
                                   " bytes (socket.max_request_bytes); ignored"));
      else
        handleLine(client, line.text);
    }
    if (client.peerClosed() && !client.hasPendingLines()) {
      close(fd, "peer closed", false);
      continue;
    }
    pending = pending || (client.hasPendingLines() && !client.held(now));
    updateInterest(client);
  }
  return pending;
}

void SocketServer::handleLine(Client& client, std::string_view line) {
  if (line.empty() || line == "\r") return;  // blank lines are harmless keep-alives
  // ?CONTROL from a client who may not send it is refused before its argument is parsed.
  constexpr std::string_view kControl = "?CONTROL=";
  if (line.substr(0, kControl.size()) == kControl && !policy_.allowed(client.peer()))
    return reply(client, permissionDenied(client));
  ParseResult parsed = parseRequest(line);
  if (!parsed.request) return reply(client, errorMessage(parsed.error));
  const Request& r = *parsed.request;
  switch (r.command) {
    case Command::version:
      return reply(client, versionMessage(release_));
    case Command::watch: {
      const WatchRequest& w = r.watch;
      if (w.enable) client.watching = *w.enable;
      if (w.pose) client.watchPose = *w.pose;
      if (w.knobs) client.watchKnobs = *w.knobs;
      if (w.energy) client.watchEnergy = *w.energy;
      return reply(client,
                   watchMessage(client.watching, client.watchPose, client.watchKnobs, client.watchEnergy));
    }
    case Command::poll:
      return reply(client, pollMessage());
    case Command::map:
      if (!lastMap_)
        return reply(client, errorMessage("?MAP: no navigation grid yet (output.navmap: a settings file saying "
                                          "which way is up; the grid comes at the first output.navmap_period_s)"));
      return deliverBulk(client, lastMap_, client.lastMap, "?MAP", "grid");
    case Command::cloud:
      if (!lastCloud_)
        return reply(client, errorMessage("?CLOUD: no map cloud yet (output.navmap with octomap_resolution_m above 0; "
                                          "the cloud comes with the grid, at the first output.navmap_period_s)"));
      return deliverBulk(client, lastCloud_, client.lastCloud, "?CLOUD", "cloud");
    case Command::status: {
      nlohmann::json s = state_.status();
      s["clients"] = clients_.size();
      s["client_messages_dropped"] = messagesDropped_;
      s["clients_disconnected"] = clientsDisconnected_;
      s["accept_pauses"] = acceptPauses_;
      return reply(client, statusMessage(std::move(s)));
    }
    case Command::odom:
      try {
        nlohmann::json result = state_.odometry(r.odom);
        result["class"] = "ODOM";
        return reply(client, result);
      } catch (const Error& e) {
        return reply(client, errorMessage(e.what()));
      }
    case Command::control: {
      if (!policy_.allowed(client.peer())) return reply(client, permissionDenied(client));
      try {
        nlohmann::json result = state_.control(r.control);
        result["class"] = "CONTROL";
        spdlog::info("socket: ?CONTROL from pid {} uid {}: {}", client.peer().pid, client.peer().uid,
                     std::string(line.substr(0, 200)));
        return reply(client, result);
      } catch (const Error& e) {
        return reply(client, errorMessage(e.what()));
      }
    }
  }
}

nlohmann::json SocketServer::permissionDenied(const Client& client) const {
  return errorMessage("?CONTROL: permission denied for uid " + std::to_string(client.peer().uid) +
                      "; allowed: " + policy_.describe() + " (socket.control_group)");
}

nlohmann::json SocketServer::pollMessage() const {
  return {{"class", "POLL"},
          {"frames", framesPublished_},
          {"pose", lastPose_ ? *lastPose_ : nlohmann::json()},
          {"knobs", lastKnobs_ ? *lastKnobs_ : nlohmann::json()},
          {"energy", lastEnergy_ ? *lastEnergy_ : nlohmann::json()}};
}

void SocketServer::reply(Client& client, const nlohmann::json& message) {
  deliver(client, makeLine(message));
}

void SocketServer::deliver(Client& client, const Line& line) {
  if (!client.send(line)) ++messagesDropped_;
  if (!client.flush()) return;  // the read path or the next event closes it
  updateInterest(client);
}

void SocketServer::deliverBulk(Client& client, const Line& line, Client::BulkSent& sent, const char* request,
                               const char* what) {
  const auto now = SteadyClock::now();
  const std::chrono::duration<double> since = now - sent.at;
  const std::chrono::duration<double> interval = kSameBulkReplyInterval;
  if (sent.line == line && since < interval) {
    const double retry = std::max(0.01, std::ceil((interval - since).count() * 100.0) / 100.0);
    char text[320];
    std::snprintf(text, sizeof text,
                  "%s: this connection was sent the same %s %.2f s ago; a connection gets the same one at most "
                  "once every %.1f s (a new one comes every output.navmap_period_s); ask again in %.2f s",
                  request, what, since.count(), interval.count(), retry);
    nlohmann::json e = errorMessage(text);
    e["retry_after_s"] = retry;
    // Its further requests wait as long: a flood of ?MAP gets one ERROR and one MAP a second, not an ERROR
    // per request (each a reply to write, which on a small board takes the SLAM thread's core).
    client.heldUntil = sent.at + kSameBulkReplyInterval;
    return reply(client, e);
  }
  if (!client.send(line)) {
    ++messagesDropped_;
  } else {
    sent.line = line;
    sent.at = now;
  }
  if (!client.flush()) return;
  updateInterest(client);
}

void SocketServer::updateInterest(Client& client) {
  // Not reading while its lines wait: its further requests stay in its socket buffer (the peer's writes
  // block), and a closed peer's level-triggered EOF does not wake the loop in vain.
  uint32_t events = 0;
  if (client.wantsInput()) events |= EPOLLIN;
  if (client.hasPendingOutput()) events |= EPOLLOUT;
  loop_.modify(client.fd(), events);
}

void SocketServer::publishFrame(const FrameReport& report) {
  ++framesPublished_;
  lastPose_ = poseMessage(report);
  lastKnobs_ = knobsMessage(report);
  const Line pose = makeLine(*lastPose_);
  const Line knobs = makeLine(*lastKnobs_);
  for (auto& [fd, client] : clients_) {
    if (!client->watching) continue;
    if (client->watchPose) deliver(*client, pose);
    if (client->watchKnobs) deliver(*client, knobs);
  }
  dropStalledClients();
}

void SocketServer::publishEnergy(const EnergyReport& report) {
  lastEnergy_ = energyMessage(report);
  const Line energy = makeLine(*lastEnergy_);
  for (auto& [fd, client] : clients_)
    if (client->watching && client->watchEnergy) deliver(*client, energy);
}

void SocketServer::publishMap(const MapReport& report) {
  lastMap_ = makeLine(mapMessage(report));
  lastCloud_ = report.cloudResolutionM > 0.0 ? makeLine(cloudMessage(report)) : Line();
}

void SocketServer::pauseAccepting(int error) {
  if (acceptPaused_) return;
  acceptPaused_ = true;
  ++acceptPauses_;
  loop_.modify(listener_, 0);
  // One line per pause (the daemon resumes at most once per tick), never one per queued connection.
  spdlog::warn("socket: accept failed: {}; not accepting clients for now ({} connected, {} pauses so far)",
               std::strerror(error), clients_.size(), acceptPauses_);
}

void SocketServer::resumeAccepting() {
  if (!acceptPaused_) return;
  acceptPaused_ = false;
  loop_.modify(listener_, EPOLLIN);
}

void SocketServer::dropStalledClients() {
  const auto now = SteadyClock::now();
  const auto limit = std::chrono::duration<double>(config_.clientStallSeconds);
  std::vector<int> stalled;
  for (auto& [fd, client] : clients_)
    if (client->stalledSince() && now - *client->stalledSince() > limit) stalled.push_back(fd);
  for (int fd : stalled) close(fd, "not reading (output queue full; socket.client_stall_s)", true);
}

void SocketServer::close(int fd, const char* why, bool byServer) {
  auto it = clients_.find(fd);
  if (it == clients_.end()) return;
  spdlog::debug("socket: client fd {} (pid {}) disconnected: {}; {} messages dropped", fd,
                it->second->peer().pid, why, it->second->dropped());
  if (byServer) ++clientsDisconnected_;
  loop_.remove(fd);
  clients_.erase(it);  // closes the fd
  resumeAccepting();   // a descriptor is free again
}

}  // namespace sb::daemon
