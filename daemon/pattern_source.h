#pragma once
// A test-pattern source (source.type "pattern"): an endless stream of synthetic depth frames of a static room
// corner (back wall, floor, side walls: every motion constrained), for soak tests of the daemon and for
// trying it without a camera or a recorded sequence. Size and rate come from source.camera (width, height,
// fps); source.pacing "fast" hands frames over as fast as the SLAM thread takes them (not live: nothing is
// dropped), "recorded" paces them at camera.fps like a camera (live: the newest frame wins).
// source.max_frames ends the stream after that many frames (0 = never).

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>

#include "daemon/capture_source.h"
#include "daemon/daemon_config.h"

namespace sb::daemon {

class PatternSource : public CaptureSource {
 public:
  explicit PatternSource(const SourceConfig& config);

  const SequenceInfo& info() const override { return info_; }
  bool live() const override { return !fast_; }
  std::optional<CapturedFrame> next() override;
  void stop() override;
  nlohmann::json status() const override;

 private:
  SourceConfig config_;
  SequenceInfo info_;
  bool fast_;
  DepthRaw depth_;  // every frame shows the same view
  std::chrono::steady_clock::time_point start_;

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopped_ = false;
  std::atomic<uint64_t> frames_{0};
};

}  // namespace sb::daemon
