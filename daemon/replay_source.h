#pragma once
// Replays a recorded sequence (any format drivers/sequence.h opens) as the daemon's source: paced at the
// recorded timestamps (times a speed factor) or as fast as the SLAM thread takes frames, and at the end
// either stops or starts over (a new pass; timestamps keep increasing).

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>

#include "daemon/capture_source.h"
#include "daemon/daemon_config.h"
#include "drivers/sequence.h"

namespace sb::daemon {

class ReplaySource : public CaptureSource {
 public:
  // Opens the sequence at once (structural errors are reported here). Throws sb::Error.
  explicit ReplaySource(const SourceConfig& config);

  const SequenceInfo& info() const override { return info_; }
  bool live() const override { return false; }
  std::optional<CapturedFrame> next() override;
  void stop() override;
  nlohmann::json status() const override;

 private:
  std::unique_ptr<FrameSource> open() const;
  // Waits until `due`; false when stopped first.
  bool waitUntil(std::chrono::steady_clock::time_point due);

  SourceConfig config_;
  SequenceOptions options_;
  std::unique_ptr<FrameSource> source_;
  SequenceInfo info_;
  bool loop_;
  bool fast_;

  // Pacing: pass-relative sequence time maps to wall time from the first frame on.
  std::optional<std::chrono::steady_clock::time_point> wallStart_;
  std::optional<double> firstTimestamp_;  // of the first frame of the first pass
  double passOffset_ = 0.0;               // seconds added to this pass's timestamps
  double lastTimestamp_ = 0.0;            // of the last frame returned (with offset)
  double framePeriod_ = 1.0 / 30.0;       // seconds, estimated from the sequence (gap between passes)

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopped_ = false;
  std::atomic<uint64_t> frames_{0};
  std::atomic<uint32_t> pass_{1};
  std::atomic<bool> ended_{false};
  std::atomic<bool> failed_{false};  // the sequence could not be read (a truncated PNG): source.state "failed"
};

}  // namespace sb::daemon
