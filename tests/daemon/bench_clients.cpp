// Load generator for scripts/bench_daemon.sh (a benchmark, not a test): N clients watch POSE and read
// everything, plus optional clients that ask for everything and never read. Waits for the socket, connects
// all, reads until the daemon closes, and prints one JSON line: per-reader POSE counts, whether each saw
// consecutive frame numbers, and when the first and last POSE arrived.
//   daemon_bench_clients SOCKET READERS SLEEPERS

#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

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

struct Reader {
  sb::UniqueFd fd;
  std::string buffer;
  long long first = -1, last = -1, count = 0;
  bool inOrder = true, open = true;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s SOCKET READERS SLEEPERS\n", argv[0]);
    return 2;
  }
  const std::string path = argv[1];
  const int readers = std::atoi(argv[2]), sleepers = std::atoi(argv[3]);
  std::vector<Reader> rs(static_cast<size_t>(readers));
  std::vector<sb::UniqueFd> ss;
  for (int attempt = 0;; ++attempt) {  // the daemon creates the socket a moment after it starts
    try {
      rs[0].fd = sb::client::connectUnix(path);
      break;
    } catch (const std::exception&) {
      if (attempt > 2000) return 1;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }
  const std::string watch = "?WATCH={\"enable\":true,\"knobs\":false}\n";
  for (int i = 1; i < readers; ++i) rs[static_cast<size_t>(i)].fd = sb::client::connectUnix(path);
  for (auto& r : rs) (void)!::send(r.fd.get(), watch.data(), watch.size(), MSG_NOSIGNAL);
  for (int i = 0; i < sleepers; ++i) {
    ss.push_back(sb::client::connectUnix(path));
    const int small = 4096;
    setsockopt(ss.back().get(), SOL_SOCKET, SO_RCVBUF, &small, sizeof small);
    const std::string all = "?WATCH={\"enable\":true}\n";
    (void)!::send(ss.back().get(), all.data(), all.size(), MSG_NOSIGNAL);
  }
  sb::UniqueFd ep(epoll_create1(0));
  for (size_t i = 0; i < rs.size(); ++i) {
    epoll_event ev{};
    ev.events = EPOLLIN;
    ev.data.u64 = i;
    epoll_ctl(ep.get(), EPOLL_CTL_ADD, rs[i].fd.get(), &ev);
  }
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  double firstPose = -1, lastPose = -1;
  int open = readers;
  while (open > 0) {
    epoll_event events[64];
    const int n = epoll_wait(ep.get(), events, 64, 120000);
    if (n <= 0) break;
    for (int e = 0; e < n; ++e) {
      Reader& r = rs[events[e].data.u64];
      char buf[65536];
      const ssize_t got = ::recv(r.fd.get(), buf, sizeof buf, 0);
      if (got <= 0) {
        epoll_ctl(ep.get(), EPOLL_CTL_DEL, r.fd.get(), nullptr);
        r.open = false;
        --open;
        continue;
      }
      r.buffer.append(buf, static_cast<size_t>(got));
      size_t start = 0;
      for (size_t nl; (nl = r.buffer.find('\n', start)) != std::string::npos; start = nl + 1) {
        const std::string_view line(r.buffer.data() + start, nl - start);
        if (line.find("\"class\":\"POSE\"") == std::string_view::npos) continue;
        const auto f = line.find("\"frame\":");
        const long long frame = std::atoll(std::string(line.substr(f + 8, 20)).c_str());
        if (r.last >= 0 && frame != r.last + 1) r.inOrder = false;
        if (r.first < 0) r.first = frame;
        r.last = frame;
        ++r.count;
        const double t = std::chrono::duration<double>(Clock::now() - t0).count();
        if (firstPose < 0) firstPose = t;
        lastPose = t;
      }
      r.buffer.erase(0, start);
    }
  }
  nlohmann::json out = {
      {"readers", readers}, {"sleepers", sleepers}, {"first_pose_s", firstPose}, {"last_pose_s", lastPose}};
  long long minCount = -1, maxCount = 0;
  bool allInOrder = true;
  for (const auto& r : rs) {
    minCount = minCount < 0 ? r.count : std::min(minCount, r.count);
    maxCount = std::max(maxCount, r.count);
    allInOrder = allInOrder && r.inOrder;
  }
  out["pose_min"] = minCount;
  out["pose_max"] = maxCount;
  out["first_frame_max"] = 0;
  for (const auto& r : rs)
    out["first_frame_max"] = std::max(out["first_frame_max"].get<long long>(), r.first);
  out["all_in_order"] = allInOrder;
  std::printf("%s\n", out.dump().c_str());
  return allInOrder ? 0 : 1;
}
