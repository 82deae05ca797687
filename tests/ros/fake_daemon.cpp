#include "tests/ros/fake_daemon.h"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace sb::test::ros_e2e {

namespace {

constexpr int kPollMs = 50;  // how often the threads look at stop_

bool writeAll(int fd, const std::string& s) {
  size_t done = 0;
  while (done < s.size()) {
    const ssize_t n = ::send(fd, s.data() + done, s.size() - done, MSG_NOSIGNAL);
    if (n <= 0) return false;
    done += static_cast<size_t>(n);
  }
  return true;
}

}  // namespace

FakeDaemon::FakeDaemon(const std::string& socketPath) : path_(socketPath) {
  listenFd_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (listenFd_ < 0 || socketPath.size() >= sizeof addr.sun_path)
    throw std::runtime_error("fake daemon: cannot make a socket at " + socketPath);
  std::strcpy(addr.sun_path, socketPath.c_str());
  if (::bind(listenFd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 || ::listen(listenFd_, 8) != 0)
    throw std::runtime_error("fake daemon: bind/listen " + socketPath + ": " + std::strerror(errno));
  acceptor_ = std::thread([this] { acceptLoop(); });
}

FakeDaemon::~FakeDaemon() {
  stop_ = true;
  acceptor_.join();
  for (auto& t : threads_) t.join();
  for (int fd : clients_) ::close(fd);
  ::close(listenFd_);
  ::unlink(path_.c_str());
}

bool FakeDaemon::watched() const {
  std::lock_guard lock(mutex_);
  return watcher_ >= 0;
}

void FakeDaemon::report(const std::string& line) {
  std::lock_guard lock(mutex_);
  if (watcher_ < 0 || !writeAll(watcher_, line + "\n"))
    throw std::runtime_error("fake daemon: no watching client to send to: " + line);
}

void FakeDaemon::acceptLoop() {
  while (!stop_) {
    pollfd p{listenFd_, POLLIN, 0};
    if (::poll(&p, 1, kPollMs) <= 0) continue;
    const int fd = ::accept4(listenFd_, nullptr, nullptr, SOCK_CLOEXEC);
    if (fd < 0) continue;
    std::lock_guard lock(mutex_);
    clients_.push_back(fd);
    threads_.emplace_back([this, fd] { serve(fd); });
  }
}

void FakeDaemon::serve(int fd) {
  {
    std::lock_guard lock(mutex_);
    if (!writeAll(fd, R"({"class":"VERSION","release":"fake","proto_major":1,"proto_minor":7})"
                      "\n"))
      return;
  }
  std::string buffer;
  while (!stop_) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, kPollMs) <= 0) continue;
    char chunk[4096];
    const ssize_t n = ::recv(fd, chunk, sizeof chunk, 0);
    if (n <= 0) break;
    buffer.append(chunk, static_cast<size_t>(n));
    for (size_t end; (end = buffer.find('\n')) != std::string::npos; buffer.erase(0, end + 1)) {
      const std::string line = buffer.substr(0, end);
      std::lock_guard lock(mutex_);
      if (line.rfind("?WATCH", 0) == 0) {
        watcher_ = fd;
      } else if (line.rfind("?ODOM=", 0) == 0) {
        const auto j = nlohmann::json::parse(line.substr(6));
        const size_t samples = j.contains("samples") ? j.at("samples").size() : 1;
        odometrySamples_ += samples;
        writeAll(fd, R"({"class":"ODOM","accepted":)" + std::to_string(samples) + "}\n");
      }
    }
  }
  std::lock_guard lock(mutex_);
  if (watcher_ == fd) watcher_ = -1;
}

}  // namespace sb::test::ros_e2e
