// Load generator for scripts/bench_flood.sh (a benchmark, not a test): one watcher of POSE and FLOODERS
// connections that pipeline REQUEST (default `?STATUS;`) as fast as the socket takes them and read every
// reply. Prints one JSON line: the watcher's POSE latency (p50, p99, max in ms), the largest gap between two
// POSEs (max_gap_ms: the frame rate's worst moment), how many replies the flooders got and how many of them
// were ERROR (a rate limit's answer, or "no grid yet").
//
// Latency: the daemon replays at the recorded pace, so frame i is released at start + timestamp_i / speed;
// a POSE's latency is its arrival minus that, less the smallest such value of the run (the fastest frame's
// capture + SLAM + delivery). It is the delay a POSE had beyond the fastest one of the same run.
//   daemon_bench_flood SOCKET FLOODERS SECONDS SPEED [FLOODER_UID|-] [REQUEST] [WARMUP_S]
// With FLOODER_UID (run as root), the watcher connects as root and the flooders as that unprivileged uid.
// WARMUP_S (default 0): seconds the watcher waits after connecting before the flood and the measurement
// start (the daemon's first frames and first navigation grid are not measured).

#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
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

struct FloodCount {
  long long replies = 0, errors = 0;
};

// The flooders: keep every socket's send buffer full of `request` and read (and count) every reply.
FloodCount flood(std::vector<sb::UniqueFd>& fds, const std::string& request, Clock::time_point until) {
  sb::UniqueFd ep(epoll_create1(0));
  for (size_t i = 0; i < fds.size(); ++i) {
    epoll_event ev{};
    ev.events = EPOLLIN | EPOLLOUT;
    ev.data.u64 = i;
    epoll_ctl(ep.get(), EPOLL_CTL_ADD, fds[i].get(), &ev);
  }
  std::string block;
  while (block.size() < 4000) block += request + "\n";  // about 4 KiB
  const std::string error = R"({"class":"ERROR")";
  std::vector<std::string> tails(fds.size());  // each socket's last bytes: an ERROR split between two reads
  FloodCount count;
  char buf[65536];
  while (Clock::now() < until) {
    epoll_event events[64];
    const int n = epoll_wait(ep.get(), events, 64, 100);
    for (int e = 0; e < n; ++e) {
      const int fd = fds[events[e].data.u64].get();
      if (events[e].events & EPOLLIN) {
        const ssize_t got = ::recv(fd, buf, sizeof buf, MSG_DONTWAIT);
        if (got > 0) {
          count.replies += std::count(buf, buf + got, '\n');
          std::string& tail = tails[events[e].data.u64];
          tail.append(buf, static_cast<size_t>(got));
          for (size_t at = 0; (at = tail.find(error, at)) != std::string::npos; at += error.size()) ++count.errors;
          tail.erase(0, tail.size() - std::min(tail.size(), error.size() - 1));
        }
      }
      if (events[e].events & EPOLLOUT) (void)!::send(fd, block.data(), block.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
    }
  }
  return count;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5 || argc > 8) {
    std::fprintf(stderr, "usage: %s SOCKET FLOODERS SECONDS SPEED [FLOODER_UID|-] [REQUEST] [WARMUP_S]\n", argv[0]);
    return 2;
  }
  const std::string path = argv[1];
  const int flooders = std::atoi(argv[2]);
  const double duration = std::atof(argv[3]), speed = std::atof(argv[4]);
  const std::string uid = argc > 5 ? argv[5] : "-";
  const std::string request = argc > 6 ? argv[6] : "?STATUS;";
  const double warmup = argc > 7 ? std::atof(argv[7]) : 0.0;
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
  if (uid != "-" && setuid(static_cast<uid_t>(std::atoi(uid.c_str()))) != 0) {
    std::perror("setuid");
    return 1;
  }
  std::vector<sb::UniqueFd> fds;
  for (int i = 0; i < flooders; ++i) fds.push_back(sb::client::connectUnix(path));
  const auto after = [](double s) {
    return Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
  };
  const auto from = after(warmup), until = after(warmup + duration);
  FloodCount count;
  std::thread floodThread([&] {
    std::this_thread::sleep_until(from);
    count = flood(fds, request, until);
  });

  std::vector<double> offsets;  // arrival - timestamp / speed, seconds
  std::vector<double> arrivals;  // seconds
  std::string buffer;
  char buf[65536];
  timeval tv{0, 200000};
  setsockopt(watcher.get(), SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  while (Clock::now() < until) {
    const ssize_t got = ::recv(watcher.get(), buf, sizeof buf, 0);
    const bool measured = Clock::now() >= from;
    const double now = seconds(Clock::now());
    if (got == 0) break;
    if (got < 0) continue;
    buffer.append(buf, static_cast<size_t>(got));
    size_t start = 0;
    for (size_t nl; (nl = buffer.find('\n', start)) != std::string::npos; start = nl + 1) {
      const std::string line = buffer.substr(start, nl - start);
      if (line.find("\"class\":\"POSE\"") == std::string::npos) continue;
      const auto j = nlohmann::json::parse(line, nullptr, false);
      if (!measured || !j.is_object() || !j.contains("timestamp")) continue;
      offsets.push_back(now - j["timestamp"].get<double>() / speed);
      arrivals.push_back(now);
    }
    buffer.erase(0, start);
  }
  floodThread.join();
  std::vector<double> latencyMs;
  if (!offsets.empty()) {
    const double best = *std::min_element(offsets.begin(), offsets.end());
    for (double o : offsets) latencyMs.push_back((o - best) * 1000.0);
  }
  double maxGap = -1;  // the first gap counts from the start of the measurement
  for (size_t i = 0; i < arrivals.size(); ++i)
    maxGap = std::max(maxGap, arrivals[i] - (i == 0 ? seconds(from) : arrivals[i - 1]));
  const nlohmann::json out = {{"flooders", flooders},
                              {"request", request},
                              {"poses", latencyMs.size()},
                              {"p50_ms", percentile(latencyMs, 50)},
                              {"p99_ms", percentile(latencyMs, 99)},
                              {"max_ms", percentile(latencyMs, 100)},
                              {"max_gap_ms", maxGap < 0 ? -1.0 : maxGap * 1000.0},
                              {"replies", count.replies},
                              {"error_replies", count.errors}};
  std::printf("%s\n", out.dump().c_str());
  return latencyMs.empty() ? 1 : 0;
}
