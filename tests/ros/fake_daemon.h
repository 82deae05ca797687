#pragma once
// A stand-in for slamboosterd's socket in the bridge's system tests (issue 57): greets every client with
// VERSION, answers ?ODOM with ODOM (accepting each sample) and anything else but ?WATCH with nothing, and
// lets the test write report lines (POSE, KNOBS) to the client that sent ?WATCH. So a test can script what
// the real daemon cannot be made to do on cue: a relocalisation's jump, a lost stretch.

#include <atomic>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace sb::test::ros_e2e {

class FakeDaemon {
 public:
  explicit FakeDaemon(const std::string& socketPath);
  ~FakeDaemon();
  FakeDaemon(const FakeDaemon&) = delete;
  FakeDaemon& operator=(const FakeDaemon&) = delete;

  // Whether a client has sent ?WATCH.
  bool watched() const;
  // Writes one line (a JSON object, without the newline) to the watching client. Throws std::runtime_error
  // when there is none or the write fails.
  void report(const std::string& line);
  // ?ODOM samples answered so far.
  size_t odometrySamples() const { return odometrySamples_; }

 private:
  void acceptLoop();
  void serve(int fd);

  std::string path_;
  int listenFd_ = -1;
  std::atomic<bool> stop_{false};
  std::atomic<size_t> odometrySamples_{0};
  mutable std::mutex mutex_;
  int watcher_ = -1;
  std::vector<int> clients_;
  std::vector<std::thread> threads_;
  std::thread acceptor_;
};

}  // namespace sb::test::ros_e2e
