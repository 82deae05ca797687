#include "tests/daemon/server_harness.h"

#include <poll.h>
#include <sys/socket.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <future>

#include "client/connection.h"
#include "core/error.h"
#include "daemon/frame_report.h"

namespace sb::test {

nlohmann::json ScriptedState::status() {
  return {{"state", "running"},
          {"source",
           {{"type", "replay"}, {"path", "/seq"}, {"live", false}, {"state", "running"}, {"frames", 3}}},
          {"controller", "fixed"},
          {"meter", "none"},
          {"fps", 30.0},
          {"frames", 3},
          {"drops", 0},
          {"uptime_s", 1.0}};
}

nlohmann::json ScriptedState::odometry(const daemon::OdomRequest& request) {
  return daemon::addOdomSamples(odometryTrack, request);
}

nlohmann::json ScriptedState::control(const daemon::ControlRequest& request) {
  if (request.controller && *request.controller == "nosuch")
    throw Error("?CONTROL: unknown controller 'nosuch' (known: fixed, slambooster)");
  nlohmann::json reply = {{"ok", true}};
  if (request.controller) reply["controller"] = *request.controller;
  nlohmann::json pinned = nlohmann::json::object();
  for (const auto& [k, v] : request.pin) pinned[k] = v;
  reply["pinned"] = pinned;
  controls.push_back(reply.dump());
  return reply;
}

daemon::FrameReport scriptedFrame(uint64_t n) {
  // A record as the runner makes it, published through the daemon's one projection of a record.
  FrameRecord record;
  FrameResult& r = record.result;
  r.frame = static_cast<decltype(r.frame)>(n);
  r.timestamp = 100.0 + 0.5 * static_cast<double>(n);
  r.T_camera_to_world = Eigen::Isometry3d::Identity();
  r.T_camera_to_world.translation() = Eigen::Vector3d(0.25 * static_cast<double>(n), 1.0, 2.0);
  r.tracked = n % 5 != 4;
  r.poseOverridden = n % 5 == 4;
  record.state = r.tracked ? TrackingState::good : TrackingState::lost;
  r.velocity = 0.25;
  r.times.ms[static_cast<int>(Stage::track)] = 12.5;
  record.controller = "fixed";
  return daemon::frameReport(record, {});
}

ServerHarness::ServerHarness(daemon::SocketConfig config, uid_t daemonUid) : config_(std::move(config)) {
  // Under /tmp, not the build tree: a Unix socket path must stay under 108 bytes wherever the tree is.
  char dir[] = "/tmp/sb-daemon-test-XXXXXX";
  if (!mkdtemp(dir)) throw Error("mkdtemp failed");
  dir_ = dir;
  std::filesystem::permissions(dir_, std::filesystem::perms::owner_all | std::filesystem::perms::group_exec |
                                         std::filesystem::perms::others_exec);
  path_ = dir_ + "/s.sock";
  listener_ = daemon::openListeningSocket(path_, config_.mode);
  server_ = std::make_unique<daemon::SocketServer>(loop_, listener_.fd.get(), config_,
                                                   daemon::ControlPolicy(daemonUid, config_.controlGroup),
                                                   state, "test-release");
  mailbox_ = std::make_unique<daemon::Mailbox>(loop_, 4096);
  thread_ = std::thread([this] { loop_.run(); });
}

ServerHarness::~ServerHarness() {
  mailbox_->post([this] {
    server_.reset();
    loop_.stop();
  });
  thread_.join();
  listener_ = daemon::ListeningSocket{};
  std::filesystem::remove_all(dir_);
}

void ServerHarness::publishFrame(const daemon::FrameReport& report) {
  mailbox_->post([this, report] { server_->publishFrame(report); });
}

void ServerHarness::publishMap(const daemon::MapReport& report) {
  mailbox_->post([this, report] { server_->publishMap(report); });
}

void ServerHarness::publishEnergy(const EnergyReport& report) {
  mailbox_->post([this, report] { server_->publishEnergy(report); });
}

void ServerHarness::sync(const std::function<void(daemon::SocketServer&)>& fn) {
  std::promise<void> done;
  mailbox_->post([&] {
    fn(*server_);
    done.set_value();
  });
  done.get_future().wait();
}

LineClient::LineClient(const std::string& path) : fd_(client::connectUnix(path)) {}

void LineClient::send(const std::string& bytes) {
  size_t off = 0;
  while (off < bytes.size()) {
    const ssize_t n = ::send(fd_.get(), bytes.data() + off, bytes.size() - off, MSG_NOSIGNAL);
    if (n <= 0) throw Error("LineClient: send failed");
    off += static_cast<size_t>(n);
  }
}

std::string LineClient::readLine(int timeoutMs) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeoutMs);
  while (true) {
    const auto nl = buffer_.find('\n');
    if (nl != std::string::npos) {
      std::string line = buffer_.substr(0, nl);
      buffer_.erase(0, nl + 1);
      return line;
    }
    if (eof_) return "";
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return "";
    pollfd p{fd_.get(), POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(left.count())) <= 0) return "";
    char buf[65536];
    const ssize_t n = ::recv(fd_.get(), buf, sizeof buf, 0);
    if (n <= 0) {
      eof_ = true;
      continue;
    }
    buffer_.append(buf, static_cast<size_t>(n));
  }
}

bool LineClient::closedWithin(int timeoutMs) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeoutMs);
  while (!eof_ && std::chrono::steady_clock::now() < deadline) {
    buffer_.clear();
    readLine(50);
  }
  return eof_;
}

}  // namespace sb::test
