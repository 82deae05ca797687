#include "daemon/replay_source.h"

#include "core/error.h"

namespace sb::daemon {

ReplaySource::ReplaySource(const SourceConfig& config)
    : config_(config), loop_(config.atEnd == "loop"), fast_(config.pacing == "fast") {
  if (config_.path.empty())
    throw ConfigError("source.path is empty: set it to a sequence directory (TUM layout), a .raw or a .bag file");
  if (config_.depthScale > 0) options_.depthScale = config_.depthScale;
  options_.maxFrames = config_.maxFrames;
  options_.depthTopic = config_.depthTopic;
  options_.prefetchThreads = 1;  // decoding must not compete with the SLAM thread for the big cores
  options_.prefetchDepth = 4;
  source_ = open();
  info_ = source_->info();
}

std::unique_ptr<FrameSource> ReplaySource::open() const {
  return openSequence(config_.path, options_);
}

bool ReplaySource::waitUntil(std::chrono::steady_clock::time_point due) {
  std::unique_lock lock(mutex_);
  return !wake_.wait_until(lock, due, [&] { return stopped_; });
}

std::optional<CapturedFrame> ReplaySource::next() {
  bool restart = false;
  uint64_t framesThisPass = 0;  // only meaningful for detecting an empty sequence below
  while (true) {
    {
      std::lock_guard lock(mutex_);
      if (stopped_) return std::nullopt;
    }
    std::optional<DepthFrame> f;
    try {
      f = source_->next();
    } catch (...) {
      failed_ = true;  // STATUS source.state "failed", not "running"
      throw;
    }
    if (!f) {
      if (!loop_ || (frames_ == 0 && framesThisPass == 0)) {
        ended_ = true;
        return std::nullopt;
      }
      source_ = open();
      ++pass_;
      restart = true;
      passOffset_ = lastTimestamp_ + framePeriod_ - *firstTimestamp_;
      continue;
    }
    ++framesThisPass;
    if (!firstTimestamp_) {
      firstTimestamp_ = f->timestamp;
      wallStart_ = std::chrono::steady_clock::now();
    }
    f->timestamp += passOffset_;
    if (pass_ == 1 && frames_ > 0) {
      // The gap between two passes is the last frame gap of the first pass.
      const double gap = f->timestamp - lastTimestamp_;
      if (gap > 0) framePeriod_ = gap;
    }
    lastTimestamp_ = f->timestamp;
    if (!fast_) {
      const auto due =
          *wallStart_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                            std::chrono::duration<double>((f->timestamp - *firstTimestamp_) / config_.speed));
      if (!waitUntil(due)) return std::nullopt;
    }
    ++frames_;
    return CapturedFrame{std::move(*f), restart};
  }
}

void ReplaySource::stop() {
  std::lock_guard lock(mutex_);
  stopped_ = true;
  wake_.notify_all();
}

nlohmann::json ReplaySource::status() const {
  bool stopped;
  {
    std::lock_guard lock(mutex_);
    stopped = stopped_;
  }
  return {{"type", "replay"},
          {"path", info_.path},
          {"format", info_.format},
          {"live", false},
          {"state", failed_   ? "failed"
                    : ended_  ? "ended"
                    : stopped ? "stopped"
                              : "running"},
          {"pacing", config_.pacing},
          {"frames", frames_.load()},
          {"sequence_frames", info_.frameCount},
          {"pass", pass_.load()}};
}

}  // namespace sb::daemon
