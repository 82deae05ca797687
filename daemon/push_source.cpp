#include "daemon/push_source.h"

#include <poll.h>
#include <signal.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <time.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <fstream>
#include <vector>
#include <cstring>
#include <spdlog/spdlog.h>

#include "core/error.h"
#include "core/input_file.h"
#include "core/json_text.h"
#include "drivers/camera_bounds.h"

namespace sb::daemon {

namespace {

constexpr int kPollSliceMs = 100;  // how often a wait checks for stop(), SIGTERM/SIGINT and a silent client
constexpr size_t kSkipChunkBytes = size_t(1) << 16;
constexpr uint64_t kLoggedRefusals = 5;  // refused frames logged one by one; STATUS "rejected" counts them all

bool terminationPending() {
  sigset_t pending;
  sigemptyset(&pending);
  return sigpending(&pending) == 0 && (sigismember(&pending, SIGTERM) == 1 || sigismember(&pending, SIGINT) == 1);
}

double wallSeconds() {
  timespec t{};
  clock_gettime(CLOCK_REALTIME, &t);
  return t.tv_sec + t.tv_nsec * 1e-9;
}

// "pid 4242 (slambooster_ros), uid 1000": who is at the other end of `fd` (SO_PEERCRED, /proc/PID/comm).
std::string describePeer(int fd) {
  ucred cred{};
  socklen_t length = sizeof cred;
  if (::getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &cred, &length) != 0) return "an unknown client";
  std::string program;
  std::ifstream comm("/proc/" + std::to_string(cred.pid) + "/comm");
  std::getline(comm, program);
  return "pid " + std::to_string(cred.pid) + (program.empty() ? "" : " (" + quoteForMessage(program) + ")") +
         ", uid " + std::to_string(cred.uid);
}

}  // namespace

PushSource::PushSource(const SourceConfig& config)
    : config_(config), wake_(eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK)) {
  if (config_.path.empty())
    throw ConfigError("source.path is empty: for source.type \"push\" it is the socket the frames arrive on");
  if (!wake_.valid()) throw Error(std::string("eventfd failed: ") + std::strerror(errno));
  listener_ = bindListeningSocket(config_.path, config_.socketMode, "source.path");
  spdlog::info("push source: waiting on {} for the first depth frame (it sets the size and intrinsics)",
               config_.path);
  PushedFrameHeader header;
  DepthRaw depth;
  while (true) {
    if (terminationPending()) throw Error("stopped while waiting for the first frame on '" + config_.path + "'");
    if (!client_.valid() && !acceptClient(kPollSliceMs)) continue;
    if (readFrame(header, depth) == Read::frame) break;
  }
  info_.path = config_.path;
  info_.format = "push";
  info_.intrinsics = Intrinsics{static_cast<int>(header.width), static_cast<int>(header.height),
                                header.fx, header.fy, header.cx, header.cy};
  info_.depthScale = config_.depthScale > 0 ? config_.depthScale : header.depthScale;
  if (config_.depthScale > 0 && config_.depthScale != header.depthScale)
    throw ConfigError("source.depth_scale = " + std::to_string(config_.depthScale) +
                      " but the pushed frames have " + std::to_string(header.depthScale) +
                      " raw units per metre: set it to 0 (from the stream) or push at that scale");
  streamStarted_ = true;
  first_ = DepthFrame{index_++, header.timestamp, std::move(depth)};
  ++frames_;
}

bool PushSource::stopRequested() const { return stopped_ || (!streamStarted_ && terminationPending()); }

bool PushSource::acceptClient(int timeoutMs) {
  pollfd fds[2] = {{listener_.fd.get(), POLLIN, 0}, {wake_.get(), POLLIN, 0}};
  const int r = ::poll(fds, 2, timeoutMs);
  if (r <= 0 || (fds[1].revents & POLLIN) || !(fds[0].revents & POLLIN)) return false;
  UniqueFd c(::accept4(listener_.fd.get(), nullptr, nullptr, SOCK_CLOEXEC));
  if (!c.valid()) return false;
  const std::string peer = describePeer(c.get());
  // A client that had already closed before it was accepted: what it sent is stale (it waited behind another
  // client); dropped unread.
  pollfd hangup{c.get(), POLLRDHUP, 0};
  if (::poll(&hangup, 1, 0) == 1 && (hangup.revents & (POLLRDHUP | POLLHUP))) {
    spdlog::warn("push source {}: {} had already closed its connection when it was accepted; what it sent is "
                 "dropped unread (stale)", config_.path, peer);
    return false;
  }
  client_ = std::move(c);
  peer_ = peer;
  ++connections_;
  connected_ = true;
  silent_ = false;
  spdlog::info("push source: {} connected to {}", peer_, config_.path);
  return true;
}

PushSource::Fill PushSource::readExactly(uint8_t* data, size_t bytes, bool within) {
  size_t off = 0;
  auto lastByte = std::chrono::steady_clock::now();
  while (off < bytes) {
    pollfd fds[2] = {{client_.get(), POLLIN, 0}, {wake_.get(), POLLIN, 0}};
    const int r = ::poll(fds, 2, kPollSliceMs);
    if (r < 0 && errno == EINTR) continue;
    if (r < 0 || (fds[1].revents & POLLIN) || stopRequested()) return Fill::stopped;
    if (!(fds[0].revents & (POLLIN | POLLHUP | POLLERR))) {
      const double idle = std::chrono::duration<double>(std::chrono::steady_clock::now() - lastByte).count();
      if (idle < config_.pushTimeoutSeconds) continue;
      // Silent for source.push_timeout_s, within a frame or between two: named and closed, whether or not
      // another client waits (a pusher that holds the socket and sends nothing must not hold it for ever).
      spdlog::warn("push source {}: {} has sent nothing for {:.1f} s {} (source.push_timeout_s): closing it",
                   config_.path, peer_, idle, within || off > 0 ? "within a frame" : "between frames");
      silent_ = true;
      return Fill::silent;
    }
    const ssize_t n = ::recv(client_.get(), data + off, bytes - off, 0);
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (n <= 0) return Fill::closed;
    off += static_cast<size_t>(n);
    lastByte = std::chrono::steady_clock::now();
    silent_ = false;
  }
  return Fill::ok;
}

bool PushSource::skip(size_t bytes) {
  std::vector<uint8_t> sink(std::min(bytes, kSkipChunkBytes));
  for (size_t left = bytes; left > 0;) {
    const size_t n = std::min(left, sink.size());
    if (readExactly(sink.data(), n, true) != Fill::ok) return false;
    left -= n;
  }
  return true;
}

std::optional<std::string> PushSource::refusal(const PushedFrameHeader& h) const {
  const Intrinsics k{static_cast<int>(h.width), static_cast<int>(h.height), h.fx, h.fy, h.cx, h.cy};
  if (!streamStarted_) {  // the first frame: the bounds every camera door shares (drivers/camera_bounds.h)
    if (const auto bound = cameraOutOfBounds(k, h.depthScale, config_.maxFramePixels))
      return cameraBoundMessage("a pushed frame's header", *bound, k) +
             (std::string(bound->name) == "width x height" ? " (raise source.max_frame_pixels for a bigger camera)"
                                                            : "");
    return std::nullopt;
  }
  const Intrinsics& s = info_.intrinsics;
  if (k.width != s.width || k.height != s.height || k.fx != s.fx || k.fy != s.fy || k.cx != s.cx ||
      k.cy != s.cy || h.depthScale != info_.depthScale)
    return "a " + std::to_string(h.width) + "x" + std::to_string(h.height) + " frame (fx " + std::to_string(h.fx) +
           ", scale " + std::to_string(h.depthScale) + ") differs from the stream's first (" +
           std::to_string(s.width) + "x" + std::to_string(s.height) + ", fx " + std::to_string(s.fx) + ", scale " +
           std::to_string(info_.depthScale) + "); restart slamboosterd to change the camera";
  return std::nullopt;
}

PushSource::Read PushSource::readFrame(PushedFrameHeader& header, DepthRaw& depth) {
  uint8_t head[kPushedHeaderBytes];
  const auto closed = [&](Fill why, const std::string& error) {
    if (why == Fill::stopped) return Read::stopped;
    if (!error.empty())
      spdlog::error("push source {}: {} from {}; closing that client", config_.path, error, peer_);
    else if (why == Fill::silent)
      spdlog::warn("push source {}: closed {} (silent); waiting for another", config_.path, peer_);
    else
      spdlog::info("push source: {} went away from {}; waiting for another", peer_, config_.path);
    client_.reset();
    connected_ = false;
    silent_ = false;
    return Read::closed;
  };
  if (const Fill f = readExactly(head, sizeof head, false); f != Fill::ok) return closed(f, "");
  try {
    header = decodePushedHeader(head);
  } catch (const Error& e) {
    return closed(Fill::closed, e.what());  // the byte stream cannot be resynchronised
  }
  const auto refuse = [&](const std::string& why) {
    if (rejected_++ < kLoggedRefusals || !streamStarted_)
      spdlog::error("push source {}: frame refused: {}; the stream goes on", config_.path, why);
    return Read::refused;
  };
  if (const auto why = refusal(header)) {
    if (!skip(pushedPayloadBytes(header))) return closed(Fill::closed, "");
    return refuse(*why);
  }
  depth.resize(static_cast<int>(header.width), static_cast<int>(header.height));
  if (const Fill f = readExactly(reinterpret_cast<uint8_t*>(depth.data()), pushedPayloadBytes(header), true);
      f != Fill::ok)
    return closed(f, "");
  if (const auto why = stamps_.check(header.timestamp)) return refuse("its " + *why);
  for (auto& v : depth.pixels())
    if (v == 0xFFFF) v = 0;  // the sequence contract: every invalid reading is 0
  lastAgeMs_ = (wallSeconds() - header.timestamp) * 1e3;
  return Read::frame;
}

std::optional<CapturedFrame> PushSource::next() {
  if (first_) {
    CapturedFrame f{std::move(*first_), false};
    first_.reset();
    return f;
  }
  PushedFrameHeader header;
  DepthRaw depth;
  while (!stopped_) {
    if (!client_.valid()) {
      acceptClient(-1);
      continue;
    }
    const Read r = readFrame(header, depth);
    if (r == Read::stopped) break;
    if (r != Read::frame) continue;
    ++frames_;
    return CapturedFrame{DepthFrame{index_++, header.timestamp, std::move(depth)}, false};
  }
  return std::nullopt;
}

void PushSource::stop() {
  stopped_ = true;
  const uint64_t one = 1;
  [[maybe_unused]] const ssize_t n = ::write(wake_.get(), &one, sizeof one);
}

nlohmann::json PushSource::status() const {
  return {{"type", "push"},
          {"path", info_.path},
          {"live", true},
          {"state", stopped_ ? "stopped" : !connected_ ? "waiting" : silent_ ? "silent" : "receiving"},
          {"frames", frames_.load()},
          {"rejected", rejected_.load()},
          {"connections", connections_.load()},
          // Meaningful when the client stamps frames with the wall clock (a live ROS camera driver does).
          {"last_arrival_age_ms", lastAgeMs_.load()}};
}

}  // namespace sb::daemon
