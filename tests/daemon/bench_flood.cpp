// Load generator for scripts/bench_flood.sh (a benchmark, not a test): one watcher of POSE and FLOODERS
// connections that pipeline `?STATUS;` requests as fast as the socket takes them and read every reply.
// Prints one JSON line: the watcher's POSE latency (p50, p99, max in ms) and how many STATUS replies the
// flooders got.
//
// Latency: the daemon replays at the recorded pace, so frame i is released at start + timestamp_i / speed;
// a POSE's latency is its arrival minus that, less the smallest such value of the run (the fastest frame's
// capture + SLAM + delivery). It is the delay a POSE had beyond the fastest one of the same run.
//   daemon_bench_flood SOCKET FLOODERS SECONDS SPEED [FLOODER_UID]
// With FLOODER_UID (run as root), the watcher connects as root and the flooders as that unprivileged uid.

#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "client/connection.h"
#include "core/unique_fd.h"

namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point t) { return std::chrono::duration<double>(t.time_since_epoch()).count(); }

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return -1;
  std::sort(v.begin(), v.end());
  const size_t i = std::min(v.size() - 1, static_cast<size_t>(p / 100.0 * static_cast<double>(v.size())));
  return v[i];
}

// The flooders: keep every socket's send buffer full of `?STATUS;` and read (and count) every reply.
long long flood(std::vector<sb::UniqueFd>& fds, Clock::time_point until) {
  sb::UniqueFd ep(epoll_create1(0));
  for (size_t i = 0; i < fds.size(); ++i) {
    epoll_event ev{};
    ev.events = EPOLLIN | EPOLLOUT;
    ev.data.u64 = i;
    epoll_ctl(ep.get(), EPOLL_CTL_ADD, fds[i].get(), &ev);
  }
  std::string block;
  for (int i = 0; i < 455; ++i) block += "?STATUS;\n";  // about 4 KiB
  long long replies = 0;
  char buf[65536];
  while (Clock::now() < until) {
    epoll_event events[64];
    const int n = epoll_wait(ep.get(), events, 64, 100);
    for (int e = 0; e < n; ++e) {
      const int fd = fds[events[e].data.u64].get();
      if (events[e].events & EPOLLIN) {
        const ssize_t got = ::recv(fd, buf, sizeof buf, MSG_DONTWAIT);
        if (got > 0) replies += std::count(buf, buf + got, '\n');
      }
      if (events[e].events & EPOLLOUT) (void)!::send(fd, block.data(), block.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
    }
  }
  return replies;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5 && argc != 6) {
    std::fprintf(stderr, "usage: %s SOCKET FLOODERS SECONDS SPEED [FLOODER_UID]\n", argv[0]);
    return 2;
  }
  const std::string path = argv[1];
  const int flooders = std::atoi(argv[2]);
  const double duration = std::atof(argv[3]), speed = std::atof(argv[4]);
  sb::UniqueFd watcher;
  for (int attempt = 0;; ++attempt) {  // the daemon creates the socket a moment after it starts
    try {
      watcher = sb::client::connectUnix(path);
      break;
    } catch (const std::exception&) {
      if (attempt > 4000) return 1;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }
  const std::string watch = "?WATCH={\"enable\":true,\"knobs\":false,\"energy\":false}\n";
  (void)!::send(watcher.get(), watch.data(), watch.size(), MSG_NOSIGNAL);
  if (argc == 6 && setuid(static_cast<uid_t>(std::atoi(argv[5]))) != 0) {
    std::perror("setuid");
    return 1;
  }
  std::vector<sb::UniqueFd> fds;
  for (int i = 0; i < flooders; ++i) fds.push_back(sb::client::connectUnix(path));
  const auto until = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(duration));
  std::atomic<long long> replies{0};
  std::thread floodThread([&] { replies = flood(fds, until); });

  std::vector<double> offsets;  // arrival - timestamp / speed, seconds
  std::string buffer;
  char buf[65536];
  timeval tv{0, 200000};
  setsockopt(watcher.get(), SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  while (Clock::now() < until) {
    const ssize_t got = ::recv(watcher.get(), buf, sizeof buf, 0);
    const double now = seconds(Clock::now());
    if (got == 0) break;
    if (got < 0) continue;
    buffer.append(buf, static_cast<size_t>(got));
    size_t start = 0;
    for (size_t nl; (nl = buffer.find('\n', start)) != std::string::npos; start = nl + 1) {
      const std::string line = buffer.substr(start, nl - start);
      if (line.find("\"class\":\"POSE\"") == std::string::npos) continue;
      const auto j = nlohmann::json::parse(line, nullptr, false);
      if (j.is_object() && j.contains("timestamp")) offsets.push_back(now - j["timestamp"].get<double>() / speed);
    }
    buffer.erase(0, start);
  }
  floodThread.join();
  std::vector<double> latencyMs;
  if (!offsets.empty()) {
    const double best = *std::min_element(offsets.begin(), offsets.end());
    for (double o : offsets) latencyMs.push_back((o - best) * 1000.0);
  }
  const nlohmann::json out = {{"flooders", flooders},
                              {"poses", latencyMs.size()},
                              {"p50_ms", percentile(latencyMs, 50)},
                              {"p99_ms", percentile(latencyMs, 99)},
                              {"max_ms", percentile(latencyMs, 100)},
                              {"status_replies", replies.load()}};
  std::printf("%s\n", out.dump().c_str());
  return latencyMs.empty() ? 1 : 0;
}
