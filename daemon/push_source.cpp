#include "daemon/push_source.h"

#include <poll.h>
#include <signal.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <time.h>

#include <cerrno>
#include <cstring>
#include <spdlog/spdlog.h>

#include "core/error.h"

namespace sb::daemon {

namespace {

constexpr unsigned kSocketMode = 0660;      // like the daemon's own socket: the service's user and group
constexpr int kStartupPollMs = 100;         // how often the wait for the first frame checks for SIGTERM/SIGINT

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

}  // namespace

PushSource::PushSource(const SourceConfig& config)
    : config_(config), wake_(eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK)) {
  if (config_.path.empty())
    throw ConfigError("source.path is empty: for source.type \"push\" it is the socket the frames arrive on");
  if (!wake_.valid()) throw Error(std::string("eventfd failed: ") + std::strerror(errno));
  listener_ = bindListeningSocket(config_.path, kSocketMode);
  spdlog::info("push source: waiting on {} for the first depth frame (it sets the size and intrinsics)",
               config_.path);
  PushedFrameHeader header;
  DepthRaw depth;
  while (true) {
    if (terminationPending()) throw Error("stopped while waiting for the first frame on '" + config_.path + "'");
    if (!client_.valid() && !acceptClient(kStartupPollMs)) continue;
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
  first_ = DepthFrame{index_++, header.timestamp, std::move(depth)};
  ++frames_;
}

bool PushSource::acceptClient(int timeoutMs) {
  pollfd fds[2] = {{listener_.fd.get(), POLLIN, 0}, {wake_.get(), POLLIN, 0}};
  const int r = ::poll(fds, 2, timeoutMs);
  if (r <= 0 || (fds[1].revents & POLLIN) || !(fds[0].revents & POLLIN)) return false;
  UniqueFd c(::accept4(listener_.fd.get(), nullptr, nullptr, SOCK_CLOEXEC));
  if (!c.valid()) return false;
  client_ = std::move(c);
  ++connections_;
  connected_ = true;
  spdlog::info("push source: a client connected to {}", config_.path);
  return true;
}

bool PushSource::readExactly(uint8_t* data, size_t bytes) {
  size_t off = 0;
  while (off < bytes) {
    pollfd fds[2] = {{client_.get(), POLLIN, 0}, {wake_.get(), POLLIN, 0}};
    const int r = ::poll(fds, 2, -1);
    if (r < 0 && errno == EINTR) continue;
    if (r < 0 || (fds[1].revents & POLLIN)) return false;
    const ssize_t n = ::recv(client_.get(), data + off, bytes - off, 0);
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (n <= 0) return false;
    off += static_cast<size_t>(n);
  }
  return true;
}

PushSource::Read PushSource::readFrame(PushedFrameHeader& header, DepthRaw& depth) {
  uint8_t head[kPushedHeaderBytes];
  const auto closed = [&](const std::string& why) {
    if (stopped_) return Read::stopped;
    if (!why.empty()) spdlog::error("push source {}: {}; closing that client", config_.path, why);
    else spdlog::info("push source: the client of {} went away; waiting for another", config_.path);
    client_.reset();
    connected_ = false;
    return Read::closed;
  };
  if (!readExactly(head, sizeof head)) return closed("");
  try {
    header = decodePushedHeader(head);
  } catch (const Error& e) {
    return closed(e.what());  // the byte stream cannot be resynchronised
  }
  depth.resize(static_cast<int>(header.width), static_cast<int>(header.height));
  if (!readExactly(reinterpret_cast<uint8_t*>(depth.data()), pushedPayloadBytes(header))) return closed("");
  for (auto& v : depth.pixels())
    if (v == 0xFFFF) v = 0;  // the sequence contract: every invalid reading is 0
  lastAgeMs_ = (wallSeconds() - header.timestamp) * 1e3;
  return Read::frame;
}

bool PushSource::matchesStream(const PushedFrameHeader& h) const {
  const Intrinsics& k = info_.intrinsics;
  return static_cast<int>(h.width) == k.width && static_cast<int>(h.height) == k.height && h.fx == k.fx &&
         h.fy == k.fy && h.cx == k.cx && h.cy == k.cy && h.depthScale == info_.depthScale;
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
    if (r == Read::closed) continue;
    if (!matchesStream(header)) {
      if (rejected_++ == 0)
        spdlog::error("push source {}: a {}x{} frame (fx {}, scale {}) differs from the stream's first ({}x{}, fx {}, "
                      "scale {}); such frames are dropped (restart slamboosterd to change the camera)",
                      config_.path, header.width, header.height, header.fx, header.depthScale,
                      info_.intrinsics.width, info_.intrinsics.height, info_.intrinsics.fx, info_.depthScale);
      continue;
    }
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
          {"state", stopped_ ? "stopped" : connected_ ? "receiving" : "waiting"},
          {"frames", frames_.load()},
          {"rejected", rejected_.load()},
          {"connections", connections_.load()},
          // Meaningful when the client stamps frames with the wall clock (a live ROS camera driver does).
          {"last_arrival_age_ms", lastAgeMs_.load()}};
}

}  // namespace sb::daemon
