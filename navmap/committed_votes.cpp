#include "navmap/committed_votes.h"

#include <sys/resource.h>

#include <algorithm>
#include <cerrno>
#include <chrono>

namespace sb::navmap {

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}
constexpr int kWorkerNice = 10;  // the worker's nice above the SLAM thread's (as runtime/map_slabs.cpp's)
}  // namespace

CommittedVotes::CommittedVotes(const NavMapConfig& config, double muM, size_t queueBytes)
    : config_(config), muM_(muM), queueBytes_(queueBytes) {}

CommittedVotes::~CommittedVotes() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
    for (const Job& job : queue_) queuedBytes_ -= job.bytes;
    pending_ -= queue_.size();
    queue_.clear();
  }
  work_.notify_all();
  if (worker_.joinable()) worker_.join();
}

void CommittedVotes::queue(const VoxelBox& box, const Eigen::Isometry3d& T_world_to_map,
                           std::shared_ptr<const void> owner, size_t bytes) {
  const auto start = Clock::now();
  std::unique_lock lock(mutex_);
  if (error_) {
    std::exception_ptr error = error_;
    error_ = nullptr;
    std::rethrow_exception(error);
  }
  const auto fits = [&] { return pending_ == 0 || queuedBytes_ + bytes <= queueBytes_; };
  if (!fits()) {  // back-pressure: the SLAM thread waits for the worker rather than dropping a slab
    const auto waitStart = Clock::now();
    done_.wait(lock, fits);
    stats_.waitMs += msSince(waitStart);
    ++stats_.waits;
  }
  Job job{box, T_world_to_map, std::move(owner), bytes};
  job.box.muM = muM_;
  queue_.push_back(std::move(job));
  queuedBytes_ += bytes;
  ++pending_;
  if (!worker_.joinable()) worker_ = std::thread([this] { workerLoop(); });
  work_.notify_one();
  stats_.queueMs += msSince(start);
}

void CommittedVotes::drain() {
  std::unique_lock lock(mutex_);
  done_.wait(lock, [&] { return pending_ == 0; });
  if (error_) {
    std::exception_ptr error = error_;
    error_ = nullptr;
    std::rethrow_exception(error);
  }
}

void CommittedVotes::seed(const GridVotes& grid, const VolumeVotes& cells) {
  drain();
  std::lock_guard lock(mutex_);
  grid_.merge(grid);
  cells_.merge(cells);
  stats_.cells = cells_.size();
  stats_.gridBytes = grid_.bytes();
}

CommittedStats CommittedVotes::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

void CommittedVotes::workerLoop() {
  // Below the SLAM thread (this thread only: Linux's nice is per thread), so that the votes take the time the
  // SLAM thread leaves idle; when the queue fills, or at a write, the SLAM thread waits for them.
  errno = 0;
  const int nice = getpriority(PRIO_PROCESS, 0);
  if (errno == 0) setpriority(PRIO_PROCESS, 0, std::min(nice + kWorkerNice, 19));  // best effort
  std::unique_lock lock(mutex_);
  for (;;) {
    work_.wait(lock, [&] { return stop_ || !queue_.empty(); });
    if (stop_) return;  // the destructor dropped the queue
    Job job = std::move(queue_.front());
    queue_.pop_front();
    lock.unlock();
    // grid_ and cells_ are this thread's until pending_ is 0 again (the reader drains first).
    const auto start = Clock::now();
    std::exception_ptr failure;
    try {
      voteGrid(job.box, job.T_world_to_map, config_, grid_);
      voteVolume(job.box, job.T_world_to_map, config_, cells_);
    } catch (...) {
      failure = std::current_exception();
    }
    const double ms = msSince(start);
    const size_t cells = cells_.size(), gridBytes = grid_.bytes();
    job.owner.reset();  // the slab's copy goes when its mesh is written too
    lock.lock();
    if (failure && !error_) error_ = failure;
    ++stats_.boxes;
    stats_.voteMs += ms;
    stats_.cells = cells;
    stats_.gridBytes = gridBytes;
    queuedBytes_ -= job.bytes;
    --pending_;
    done_.notify_all();
  }
}

}  // namespace sb::navmap
